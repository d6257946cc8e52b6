// `ours` and `tile`: tangent-space direction reuse in groups of K pixels (Liu et al., "Generate Coherent Rays
// Directly", Eurographics 2024, sections 3.2 and 3.3; DESIGN.md section 2).
//
// Per frame the image is split into W x H tiles (partial tiles at the right and bottom borders keep their
// clipped size m = w' h'). Inside a tile the pixels are numbered row-major, i = 0..m-1, and
//   ours: the numbers are shuffled, s = shuffle(i) (generators/tiles.h: a full-period LCG permutation whose
//         constants change per tile and per frame), and group = s / K — so each full tile has W H / K
//         interleaved groups of K pixels spread over the tile;
//   tile: the ablation without interleaving: group = i / K, contiguous runs of the row-major numbering, the
//         same every frame.
// When K does not divide m, the last group of the tile has m mod K members. Pixels without a hit keep their
// number (so the grouping of the other pixels does not depend on what is visible) but emit no ray; a group
// with no hit pixel does nothing.
//
// Each group is classified by its hit members' materials (diffuse and emissive count as diffuse; glossy and
// specular as glossy; transmissive members always sample their own lobe and do not vote, as the paper does not
// handle transmission):
//   diffuse group  one member, chosen at random (rng(seed, frame, group id, kDimGroupDonor)), draws a
//                  cosine-weighted tangent-space direction with its own random numbers; every diffuse member
//                  uses that direction in its own tangent frame (core/sampling.h make_frame: the branchless
//                  ONB of Duff et al. depends on the normal only, so coplanar members get identical world
//                  directions). Each member's pdf (cos / pi) and weight (base colour) are its own, so every
//                  pixel's marginal direction stays cosine-distributed around its own normal.
//   glossy group   every member samples its own GGX lobe (no change from NoOpt).
//   hybrid group   glossy members sample their own lobes; the mean of their tangent-space directions,
//                  normalised, is used by every diffuse member, with pdf and weight from the member's own BSDF
//                  (this direction is not drawn from the diffuse pdf: the paper's bias, measured, not hidden).
//                  If the mean nearly cancels (the average vector is shorter than 0.01) or no glossy sample is
//                  valid, the diffuse members fall back to the diffuse-group rule (counted: hybrid_mean_fallback).
// A shared direction that ends up below a member's geometric surface (shading normal far from the geometric
// one) stays in the batch with weight 0 and is counted in below_geometric, like every generator's.
// K = 1 reproduces NoOpt bit for bit: the donor is the pixel itself and uses NoOpt's random numbers.
//
// Parameters
//   tile   WxH     8x8    each side in [1, 1024], W H <= 65536: the tile
//   k      int     8      [1, W H]: group size K
//   order  string  tile   tile | group | scanline: batch order (tile: row-major inside each tile, tiles
//                         row-major; group: inside each tile, group by group — whole groups in one warp;
//                         scanline: the image's rows)
//   seed   uint    0      [0, 2^32 - 1]: extra salt for the grouping only (shuffle constants and donors);
//                         0 uses the run's seed alone
#include <fmt/format.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "core/bsdf.h"
#include "core/error.h"
#include "core/rng.h"
#include "generators/generator.h"
#include "generators/tangent_reuse.h"
#include "generators/tiles.h"

namespace raycoh {

namespace {

bool is_diffuse_like(MaterialClass c) { return c == MaterialClass::Diffuse || c == MaterialClass::Emissive; }
bool is_glossy_like(MaterialClass c) { return c == MaterialClass::Glossy || c == MaterialClass::Specular; }

// Per-thread scratch, sized for one tile.
struct Scratch {
  std::vector<uint32_t> group_of;     // per pixel number i: group in tile
  std::vector<uint32_t> group_start;  // counting-sort offsets, size groups + 1
  std::vector<uint32_t> members;      // pixel numbers i, grouped, row-major inside a group
  std::vector<uint32_t> cursor;       // counting-sort write positions
  std::vector<uint32_t> rank;         // per pixel number i: rank among the tile's hit pixels (row-major)
  GenerationStats stats;
};

}  // namespace

TangentSpaceReuse::TangentSpaceReuse(ParamSet& params, bool interleaved) : interleaved_(interleaved) {
  tile_ = params.get_size("tile", {8, 8}, 1, 1024);
  const int area = tile_.first * tile_.second;
  if (area > 65536)
    throw Error(fmt::format("{}: tile={}x{} has {} pixels; at most 65536", params.owner(), tile_.first,
                            tile_.second, area));
  k_ = params.get_int("k", 8, 1, area);
  order_ = params.get_choice("order", "tile", {"tile", "group", "scanline"});
  salt_ = params.get_uint("seed", 0u, 0u, 0xFFFFFFFFu);
  params.finish();
  params_ = params.canonical();
}

void TangentSpaceReuse::generate(const Scene& scene, const GBuffer& g, uint32_t seed, RayBatch& out,
                                 GenerationStats& stats) {
  const TileGrid grid(g.width, g.height, tile_.first, tile_.second);
  const std::vector<uint32_t> offsets = tile_hit_offsets(g, grid);
  const std::vector<uint32_t> slots = order_ == "scanline" ? scanline_slots(g) : std::vector<uint32_t>{};
  const uint32_t total = offsets.back();
  out.width = g.width;
  out.height = g.height;
  out.frame = g.frame;
  out.resize(total, true);
  const uint32_t frame = g.frame;
  const uint32_t group_seed = seed ^ hash32(salt_);
  const uint32_t k = static_cast<uint32_t>(k_);
  const uint32_t groups_per_full_tile = static_cast<uint32_t>((tile_.first * tile_.second + k_ - 1) / k_);
  const bool group_order = order_ == "group";
  const bool scanline = order_ == "scanline";

  tbb::enumerable_thread_specific<Scratch> scratch;
  tbb::parallel_for(tbb::blocked_range<int>(0, grid.count(), 16), [&](const tbb::blocked_range<int>& range) {
    Scratch& sc = scratch.local();
    for (int t = range.begin(); t < range.end(); ++t) {
      int x0, y0, w, h;
      grid.rect(t, x0, y0, w, h);
      const uint32_t m = static_cast<uint32_t>(w * h);
      const uint32_t groups = (m + k - 1) / k;
      auto pixel_of = [&](uint32_t i) {
        return static_cast<uint32_t>((y0 + static_cast<int>(i) / w) * g.width + x0 + static_cast<int>(i) % w);
      };
      // Group every pixel number, then counting-sort the hit pixels by group (row-major inside a group).
      const TileShuffle shuffle = make_tile_shuffle(m, group_seed, frame, static_cast<uint32_t>(t));
      sc.group_of.resize(m);
      sc.rank.resize(m);
      sc.group_start.assign(groups + 1, 0);
      uint32_t hits = 0;
      for (uint32_t i = 0; i < m; ++i) {
        sc.group_of[i] = (interleaved_ ? shuffle(i) : i) / k;
        if (g.points[pixel_of(i)].valid()) {
          sc.rank[i] = hits++;
          ++sc.group_start[sc.group_of[i] + 1];
        }
      }
      if (hits == 0) continue;
      for (uint32_t q = 0; q < groups; ++q) sc.group_start[q + 1] += sc.group_start[q];
      sc.members.resize(hits);
      sc.cursor.assign(sc.group_start.begin(), sc.group_start.end() - 1);
      for (uint32_t i = 0; i < m; ++i)
        if (g.points[pixel_of(i)].valid()) sc.members[sc.cursor[sc.group_of[i]]++] = i;

      for (uint32_t q = 0; q < groups; ++q) {
        const uint32_t begin = sc.group_start[q], end = sc.group_start[q + 1];
        if (begin == end) continue;
        const uint32_t group_id = static_cast<uint32_t>(t) * groups_per_full_tile + q;
        uint32_t n_diffuse = 0, n_glossy = 0;
        for (uint32_t j = begin; j < end; ++j) {
          const MaterialClass c = g.points[pixel_of(sc.members[j])].cls;
          n_diffuse += is_diffuse_like(c);
          n_glossy += is_glossy_like(c);
        }
        const GroupType type = n_diffuse && n_glossy ? GroupType::Hybrid
                               : n_diffuse           ? GroupType::Diffuse
                               : n_glossy            ? GroupType::Glossy
                                                     : GroupType::Independent;
        ++sc.stats.groups[static_cast<int>(type)];
        // Writes member j's ray straight into its batch slot (group order: members are already grouped).
        auto emit = [&](uint32_t j, const DirectionSample& s) {
          const uint32_t i = sc.members[j];
          const uint32_t p = pixel_of(i);
          const uint32_t slot = scanline ? slots[p] : offsets[t] + (group_order ? j : sc.rank[i]);
          tally_ray(emit_ray(out, slot, g.points[p], p, s), sc.stats);
          out.tile[slot] = static_cast<uint32_t>(t);
          out.group[slot] = group_id;
          out.group_type[slot] = type;
        };

        // Glossy and transmissive members sample their own lobes with NoOpt's random numbers.
        Vec3 mean{0.f, 0.f, 0.f};
        uint32_t n_mean = 0;
        for (uint32_t j = begin; j < end; ++j) {
          const uint32_t p = pixel_of(sc.members[j]);
          const ShadingPoint& sp = g.points[p];
          if (is_diffuse_like(sp.cls)) continue;
          const DirectionSample s = sample_direction(
              bsdf_params(scene.materials[sp.material]), sp.ns, sp.ng, sp.wo, sp.front_face,
              rng_float(seed, frame, p, kDimSecondary0), rng_float(seed, frame, p, kDimSecondary1),
              rng_float(seed, frame, p, kDimSecondaryLobe));
          emit(j, s);
          if (is_glossy_like(sp.cls) && s.flags == kSampleOk) {
            const Vec3 local = make_frame(sp.ns).to_local(s.dir);
            if (local.z > 0.f) {
              mean += local;
              ++n_mean;
            }
          }
        }
        // Diffuse members: the shared tangent-space direction.
        if (n_diffuse > 0) {
          Vec3 local;
          bool from_donor = false;
          const float mean_len = length(mean);
          if (type == GroupType::Hybrid && n_mean > 0 && mean_len > 1e-2f * static_cast<float>(n_mean) &&
              mean.z > 0.f) {
            local = mean * (1.f / mean_len);
          } else {
            if (type == GroupType::Hybrid) ++sc.stats.hybrid_mean_fallback;
            // Donor: the d-th diffuse member in row-major order.
            uint32_t d = n_diffuse == 1 ? 0 : rng_u32(group_seed, frame, group_id, kDimGroupDonor) % n_diffuse;
            uint32_t donor = 0;
            for (uint32_t j = begin; j < end; ++j) {
              const uint32_t p = pixel_of(sc.members[j]);
              if (is_diffuse_like(g.points[p].cls) && d-- == 0) {
                donor = p;
                break;
              }
            }
            local = sample_cosine_hemisphere(rng_float(seed, frame, donor, kDimSecondary0),
                                             rng_float(seed, frame, donor, kDimSecondary1));
            from_donor = true;
          }
          for (uint32_t j = begin; j < end; ++j) {
            const ShadingPoint& sp = g.points[pixel_of(sc.members[j])];
            if (!is_diffuse_like(sp.cls)) continue;
            emit(j, diffuse_from_local(bsdf_params(scene.materials[sp.material]), sp.ns, sp.ng, local));
          }
          sc.stats.reused_rays += n_diffuse - (from_donor ? 1 : 0);
        }
      }
    }
  });
  stats = GenerationStats{};
  for (const Scratch& sc : scratch) merge_stats(stats, sc.stats);
}

}  // namespace raycoh
