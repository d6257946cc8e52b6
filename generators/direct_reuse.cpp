// `direct`: world-space direction reuse per tile, the paper's first attempt (Liu et al. 2024, section 3.1 and
// Fig. 1), kept as the ablation that shows why tangent space matters. In every W x H tile one hit pixel, chosen
// at random (rng(seed, frame, tile, kDimGroupDonor)), samples its own lobe with NoOpt's random numbers; every
// other non-transmissive hit pixel of the tile uses that same *world* direction, with pdf and weight from its
// own BSDF (core/bsdf.h evaluate_direction). Directions that fall below a member's shading hemisphere or
// geometric surface get weight 0 and are counted (below_shading / below_geometric): the artifacts and
// back-facing directions the paper shows. Transmissive pixels sample their own lobe. Rays are written in tile
// order (row-major inside a tile).
//
// Parameters: direct_params() below.
#include <fmt/format.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "core/own_lobe.h"
#include "core/rng.h"
#include "generators/tangent_reuse.h"
#include "generators/tiles.h"

namespace raycoh {

const ParamTable& direct_params() {
  static const ParamTable table = {
      tile_param({8, 8}, "the tile sharing one world-space direction"),
  };
  return table;
}

std::unique_ptr<Generator> make_direct_generator(ParamSet& params) { return std::make_unique<DirectReuse>(params); }

DirectReuse::DirectReuse(ParamSet& params) {
  tile_ = params.get_size("tile");
  check_tile(params.owner(), tile_);
  params.finish();
  params_ = params.canonical();
}

void DirectReuse::generate(const Scene& scene, const GBuffer& g, uint32_t seed, RayBatch& out, GenerationStats& stats) {
  const TileGrid grid(g.width, g.height, tile_.first, tile_.second);
  const MaterialTable materials(scene, g);
  const std::vector<uint32_t> offsets = tile_hit_offsets(g, grid);
  out.width = g.width;
  out.height = g.height;
  out.frame = g.frame;
  out.resize(offsets.back(), true);
  tbb::enumerable_thread_specific<GenerationStats> partial;
  const uint32_t frame = g.frame;
  tbb::parallel_for(0, grid.count(), [&](int t) {
    const uint32_t hits = offsets[t + 1] - offsets[t];
    if (hits == 0) return;
    int x0, y0, w, h;
    grid.rect(t, x0, y0, w, h);
    // The donor is the d-th hit pixel of the tile in row-major order.
    uint32_t d = rng_u32(seed, frame, static_cast<uint32_t>(t), kDimGroupDonor) % hits;
    uint32_t donor = 0;
    for (int y = y0; y < y0 + h && !donor; ++y)
      for (int x = x0; x < x0 + w; ++x) {
        const uint32_t p = static_cast<uint32_t>(y * g.width + x);
        if (g.points[p].valid() && d-- == 0) {
          donor = p + 1;
          break;
        }
      }
    --donor;
    auto own_sample = [&](uint32_t p) {
      const ShadingPoint& sp = g.points[p];
      return sample_own_lobe(materials[sp.material], sp, seed, frame, p);
    };
    const DirectionSample shared = own_sample(donor);
    uint32_t slot = offsets[t];
    for (int y = y0; y < y0 + h; ++y)
      for (int x = x0; x < x0 + w; ++x) {
        const uint32_t p = static_cast<uint32_t>(y * g.width + x);
        const ShadingPoint& sp = g.points[p];
        if (!sp.valid()) continue;
        DirectionSample s;
        if (p == donor) {
          s = shared;
        } else if (sp.cls == MaterialClass::Transmissive) {
          s = own_sample(p);
        } else {
          s = evaluate_direction(materials[sp.material], sp.ns, sp.ng, sp.wo, shared.dir);
        }
        tally_ray(emit_ray(out, slot, sp, p, s), partial.local());
        out.tile[slot] = static_cast<uint32_t>(t);
        out.group[slot] = static_cast<uint32_t>(t);
        out.group_type[slot] = GroupType::WorldShared;
        ++slot;
      }
  });
  stats = GenerationStats{};
  for (const GenerationStats& s : partial) merge_stats(stats, s);
  for (uint32_t t = 0; t < static_cast<uint32_t>(grid.count()); ++t)
    if (offsets[t + 1] > offsets[t]) {
      ++stats.groups[static_cast<int>(GroupType::WorldShared)];
      stats.reused_rays += offsets[t + 1] - offsets[t] - 1;
    }
}

}  // namespace raycoh
