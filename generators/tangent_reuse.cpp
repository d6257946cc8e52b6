// `ours` and `contiguous`: tangent-space direction reuse in groups of K pixels (Liu et al., "Generate Coherent Rays
// Directly", Eurographics 2024, sections 3.2 and 3.3; docs/design.md section 2).
//
// Per frame the image is split into W x H tiles (partial tiles at the right and bottom borders keep their
// clipped size m = w' h'). Inside a tile the pixels are numbered row-major, i = 0..m-1, and
//   ours: the numbers are shuffled, s = shuffle(i) (generators/tiles.h: a full-period LCG permutation whose
//         constants change per tile and per frame), and group = s / K — so each full tile has W H / K
//         interleaved groups of K pixels spread over the tile;
//   contiguous: the ablation without interleaving: group = i / K, contiguous runs of the row-major numbering, the
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
//   hybrid group   glossy members sample their own lobes; the diffuse members by the rule `hybrid`:
//                  paper (default, the paper's rule): the mean of the glossy members' tangent-space directions,
//                    normalised, with pdf and weight from the member's own BSDF. This direction is not drawn
//                    from the diffuse pdf, so the weight (base colour = f cos / (cos / pi)) is wrong for it: the
//                    paper's bias, measured in docs/hybrid-reuse.md (on cornell the affected pixels converge
//                    ~12% dark). If the mean nearly cancels (the average vector is shorter than 0.01) or no
//                    glossy sample is valid, the diffuse members fall back to the diffuse-group rule (counted:
//                    hybrid_mean_fallback).
//                  donor: the diffuse-group rule for the diffuse members (unbiased; coherent among them).
//                  glossy: one glossy member, chosen uniformly before sampling (rng(seed, frame, group id,
//                    kDimGroupGlossy)), lends its own sample: every diffuse member uses its direction with weight
//                    f cos / p, p the GGX pdf that drew it (tangent-space copies and rotations keep solid angle,
//                    so p is also the member's density). The pdf column stays the member's own cos / pi, the pdf
//                    next-event estimation evaluates, so the MIS weights still sum to one. A sample below its own
//                    shading surface gives the diffuse members weight 0 (still unbiased). Unbiased, but the
//                    weight is large where the glossy lobe is thin: high variance on near-specular scenes.
//                  independent: every diffuse member samples its own lobe (NoOpt's numbers; no reuse).
// The reuse frame `frame`: duff (default, the paper's): the shared direction is a tangent-space vector used in
// each member's make_frame(ns), which flips at n.z = 0 (neighbours with nearly equal normals on either side get
// directions far apart). rotate: the shared direction is a world direction around the group's reference normal
// (its donor's, a diffuse member), carried to each member by the minimal rotation from that normal to the
// member's (core/sampling.h rotate_between): continuous where normals are close, the same cos to each member's
// normal, and so the same marginal pdf (diffuse groups stay unbiased). Glossy votes are rotated to the reference
// normal before they are averaged. frame=duff with hybrid=paper is the paper's generator bit for bit.
// A shared direction that ends up below a member's geometric surface (shading normal far from the geometric
// one) stays in the batch with weight 0 and is counted in below_geometric, like every generator's.
// K = 1 reproduces NoOpt bit for bit: the donor is the pixel itself and uses NoOpt's random numbers (frame=rotate:
// the same directions; the pdf then comes from dir . ns, which may differ from NoOpt's in the last bit).
//
// Parameters: ours_params() below, shared by `ours` and `contiguous`. Batch orders: tile = row-major inside each
// tile, tiles row-major; group = inside each tile, group by group (whole groups in one warp); scanline = the
// image's rows.
#include "generators/tangent_reuse.h"

#include <fmt/format.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "core/rng.h"
#include "core/tile_grid.h"
#include "generators/generator.h"
#include "generators/grouping.h"
#include "generators/pixel_order.h"
#include "generators/tiles.h"

namespace raycoh {

namespace {

// Per-thread scratch, sized for one tile.
struct Scratch {
  std::vector<uint32_t> group_of;     // per pixel number i: group in tile
  std::vector<uint32_t> group_start;  // counting-sort offsets, size groups + 1
  std::vector<uint32_t> members;      // pixel numbers i, grouped, row-major inside a group
  std::vector<uint32_t> cursor;       // counting-sort write positions
  std::vector<uint32_t> rank;         // per pixel number i: rank among the tile's hit pixels (row-major)
  GenerationStats stats;
};

// What every tile of one frame reads.
struct FrameJob {
  const GBuffer& g;
  const GroupingConfig& config;
  const MaterialTable& materials;
  const std::vector<uint32_t>& offsets;  // first slot of each tile
  const std::vector<uint32_t>& slots;    // scanline order: slot of each pixel
  BatchView out;
};

// Groups every pixel number of tile t, then counting-sorts the hit pixels by group (row-major inside a group).
// Returns the tile's hit pixels.
uint32_t sort_tile(const FrameJob& job, uint32_t t, const TileRect& r, Scratch& sc) {
  const uint32_t m = r.area(), groups = (m + job.config.k - 1) / job.config.k;
  const TileShuffle shuffle = tile_shuffle(job.config, m, t);
  sc.group_of.resize(m);
  sc.rank.resize(m);
  sc.group_start.assign(groups + 1, 0);
  uint32_t hits = 0;
  for (uint32_t i = 0; i < m; ++i) {
    sc.group_of[i] = group_in_tile(job.config, shuffle, i);
    if (has_hit(job.g.points[r.pixel(i, job.g.width)])) {
      sc.rank[i] = hits++;
      ++sc.group_start[sc.group_of[i] + 1];
    }
  }
  if (hits == 0) return 0;
  for (uint32_t q = 0; q < groups; ++q) sc.group_start[q + 1] += sc.group_start[q];
  sc.members.resize(hits);
  sc.cursor.assign(sc.group_start.begin(), sc.group_start.end() - 1);
  for (uint32_t i = 0; i < m; ++i)
    if (has_hit(job.g.points[r.pixel(i, job.g.width)])) sc.members[sc.cursor[sc.group_of[i]]++] = i;
  return hits;
}

// The rays of group q of tile t (its members are sc.members[group_start[q] .. group_start[q + 1])).
void generate_group(const FrameJob& job, uint32_t t, const TileRect& r, uint32_t q, Scratch& sc) {
  const uint32_t begin = sc.group_start[q], end = sc.group_start[q + 1];
  if (begin == end) return;
  const GroupingConfig& c = job.config;
  const uint32_t group = group_id(c, t, q);
  auto pixel_of = [&](uint32_t j) { return r.pixel(sc.members[j], job.g.width); };
  GroupCensus census;
  for (uint32_t j = begin; j < end; ++j) census.add(job.g.points[pixel_of(j)].cls);
  const GroupType type = census.type();
  ++sc.stats.groups[static_cast<int>(type)];
  // Writes member j's ray straight into its batch slot (group order: members are already grouped).
  auto emit = [&](uint32_t j, const ShadingPoint& sp, const DirectionSample& s) {
    const uint32_t i = sc.members[j], p = pixel_of(j);
    const uint32_t slot =
        c.order == RayOrder::Scanline ? job.slots[p] : job.offsets[t] + (c.order == RayOrder::Group ? j : sc.rank[i]);
    tally_ray(write_group_ray(job.out, slot, sp, p, s, t, group, type), sc.stats);
  };

  // The donor (a diffuse member) first: its normal is the reference of frame=rotate.
  DonorSearch donor{donor_rank(c, group, census.diffuse)};
  for (uint32_t j = begin; j < end && !donor.found; ++j) donor.offer(job.g.points[pixel_of(j)].cls, pixel_of(j));
  const Vec3 ref = job.g.points[donor.found ? donor.pixel : pixel_of(begin)].ns;
  const bool reuse_glossy = type == GroupType::Hybrid && c.hybrid == HybridRule::Glossy;
  const uint32_t pick = glossy_rank(c, group, census.glossy);
  uint32_t glossy_seen = 0;
  SharedDirection picked;
  GlossyMean mean;
  for (uint32_t j = begin; j < end; ++j) {
    const uint32_t p = pixel_of(j);
    const ShadingPoint& sp = job.g.points[p];
    if (is_diffuse_like(sp.cls)) continue;
    const DirectionSample s = sample_own_lobe(job.materials[sp.material], sp, c.seed, c.frame, p);
    emit(j, sp, s);
    Vec3 local;
    if (mean_vote(c, sp, s, ref, local)) mean.add(local);
    if (reuse_glossy && is_glossy_like(sp.cls) && glossy_seen++ == pick) picked = glossy_direction(c, sp, s, ref);
  }
  if (census.diffuse == 0) return;
  const SharedDirection d = reuse_glossy ? picked : shared_direction(c, type, mean, donor.pixel, ref);
  sc.stats.hybrid_mean_fallback += d.hybrid_fallback;
  for (uint32_t j = begin; j < end; ++j) {
    const uint32_t p = pixel_of(j);
    const ShadingPoint& sp = job.g.points[p];
    if (is_diffuse_like(sp.cls)) emit(j, sp, member_direction(c, type, job.materials[sp.material], sp, p, ref, d));
  }
  sc.stats.reused_rays += reused_members(c, type, d, census.diffuse);
}

}  // namespace

const ParamTable& ours_params() {
  static const ParamTable table = {
      tile_param({8, 8}, "the tile"),
      int_param("k", 8, 1, kMaxTilePixels, "group size K, at most W H"),
      choice_param("order", "tile", ray_order_names(true), "batch order (see tangent_reuse.cpp)"),
      uint_param("seed", 0u, 0u, 0xFFFFFFFFu, "extra salt for the grouping only (shuffle and donors); 0: none"),
      choice_param("hybrid", "paper", {"paper", "donor", "glossy", "independent"},
                   "diffuse members of hybrid groups: paper = glossy mean (biased), donor / glossy / independent "
                   "(unbiased; see tangent_reuse.cpp)"),
      choice_param("frame", "duff", {"duff", "rotate"},
                   "reuse frame: duff = same tangent coordinates (seam at n.z = 0), rotate = minimal rotation "
                   "from the donor normal"),
  };
  return table;
}

std::unique_ptr<Generator> make_ours_generator(ParamSet& params) {
  return std::make_unique<TangentSpaceReuse>(params, true);
}

std::unique_ptr<Generator> make_contiguous_generator(ParamSet& params) {
  return std::make_unique<TangentSpaceReuse>(params, false);
}

TangentSpaceReuse::TangentSpaceReuse(ParamSet& params, bool interleaved) : interleaved_(interleaved) {
  tile_ = params.get_size("tile");
  check_tile(params.owner(), tile_);
  const int area = tile_.first * tile_.second;
  k_ = params.get_int_at_most("k", area);
  order_ = parse_ray_order(params.get_choice("order"));
  salt_ = params.get_uint("seed");
  const std::string hybrid = params.get_choice("hybrid");
  hybrid_ = hybrid == "donor"         ? HybridRule::Donor
            : hybrid == "glossy"      ? HybridRule::Glossy
            : hybrid == "independent" ? HybridRule::Independent
                                      : HybridRule::Paper;
  frame_ = params.get_choice("frame") == "rotate" ? ReuseFrame::Rotate : ReuseFrame::Duff;
  params.finish();
  params_ = params.canonical();
}

std::optional<BatchLayout> TangentSpaceReuse::layout() const {
  return BatchLayout{tile_.first, tile_.second, k_, to_string(order_)};
}

DeviceRecipe TangentSpaceReuse::device_recipe() const {
  DeviceRecipe r;
  r.kind = DeviceRecipe::Kind::Grouping;
  r.tile_w = tile_.first;
  r.tile_h = tile_.second;
  r.order = order_;
  r.salt_hash = hash32(salt_);
  GroupingConfig& c = r.grouping;
  c.k = static_cast<uint32_t>(k_);
  c.groups_per_full_tile = static_cast<uint32_t>((tile_.first * tile_.second + k_ - 1) / k_);
  c.interleaved = interleaved_;
  c.order = order_;
  c.hybrid = hybrid_;
  c.reuse_frame = frame_;
  return r;
}

void TangentSpaceReuse::generate(const Scene& scene, const GBuffer& g, uint32_t seed, RayBatch& out,
                                 GenerationStats& stats) {
  const TileGrid grid(g.width, g.height, tile_.first, tile_.second);
  const std::vector<uint32_t> offsets = tile_hit_offsets(g, grid);
  const std::vector<uint32_t> slots = order_ == RayOrder::Scanline ? scanline_slots(g) : std::vector<uint32_t>{};
  const MaterialTable table(scene, g);
  out.width = g.width;
  out.height = g.height;
  out.frame = g.frame;
  out.resize(offsets.back(), true);
  const GroupingConfig c = config(seed, g.frame);
  const FrameJob job{g, c, table, offsets, slots, batch_view(out)};

  tbb::enumerable_thread_specific<Scratch> scratch;
  tbb::parallel_for(tbb::blocked_range<int>(0, grid.count(), 16), [&](const tbb::blocked_range<int>& range) {
    Scratch& sc = scratch.local();
    for (int t = range.begin(); t < range.end(); ++t) {
      const TileRect r = grid.rect(t);
      if (sort_tile(job, static_cast<uint32_t>(t), r, sc) == 0) continue;
      const uint32_t groups = (r.area() + c.k - 1) / c.k;
      for (uint32_t q = 0; q < groups; ++q) generate_group(job, static_cast<uint32_t>(t), r, q, sc);
    }
  });
  stats = GenerationStats{};
  for (const Scratch& sc : scratch) merge_stats(stats, sc.stats);
}

}  // namespace raycoh
