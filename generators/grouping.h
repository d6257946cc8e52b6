// The steps of the paper's grouping (`ours` and `contiguous`), one definition for the CPU tile loop
// (generators/tangent_reuse.cpp) and the CUDA block phases (cuda/device_grouping.cu). Liu et al., "Generate
// Coherent Rays Directly", Eurographics 2024, sections 3.2-3.3; the rules are spelled out in tangent_reuse.cpp.
// Plain structs and RAYCOH_HD functions only: the two loops differ in how they walk a tile, never in what they
// compute for a pixel or a group, so their batches are equal bit for bit.
#pragma once

#include "core/batch_view.h"
#include "core/bsdf.h"
#include "core/own_lobe.h"
#include "core/platform.h"
#include "core/ray_batch.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "core/tile_grid.h"
#include "core/tile_shuffle.h"

namespace raycoh {

// One frame's grouping, as both loops read it.
struct GroupingConfig {
  uint32_t seed = 0;        // the run's seed: every pixel's own random numbers
  uint32_t group_seed = 0;  // seed ^ hash32(salt): shuffle constants and donors
  uint32_t frame = 0;
  uint32_t k = 8;                     // group size K
  uint32_t groups_per_full_tile = 8;  // ceil(W H / K): group ids are tile * this + group in tile
  bool interleaved = true;            // ours: shuffled groups; contiguous: group = i / K
  RayOrder order = RayOrder::Tile;    // batch order (core/tile_grid.h)
};

RAYCOH_HD RAYCOH_INLINE bool is_diffuse_like(MaterialClass c) {
  return c == MaterialClass::Diffuse || c == MaterialClass::Emissive;
}
RAYCOH_HD RAYCOH_INLINE bool is_glossy_like(MaterialClass c) {
  return c == MaterialClass::Glossy || c == MaterialClass::Specular;
}
RAYCOH_HD RAYCOH_INLINE bool has_hit(const ShadingPoint& sp) { return sp.prim != kNoHit; }

// Group in tile of pixel number i (tile of m pixels, tile index t).
RAYCOH_HD RAYCOH_INLINE uint32_t group_in_tile(const GroupingConfig& c, const TileShuffle& shuffle, uint32_t i) {
  return (c.interleaved ? shuffle(i) : i) / c.k;
}
RAYCOH_HD RAYCOH_INLINE TileShuffle tile_shuffle(const GroupingConfig& c, uint32_t m, uint32_t t) {
  return make_tile_shuffle(m, c.group_seed, c.frame, t);
}
RAYCOH_HD RAYCOH_INLINE uint32_t group_id(const GroupingConfig& c, uint32_t t, uint32_t q) {
  return t * c.groups_per_full_tile + q;
}

// Classification of a group by its hit members' materials (transmissive members do not vote).
struct GroupCensus {
  uint32_t count = 0, diffuse = 0, glossy = 0;
  RAYCOH_HD void add(MaterialClass c) {
    ++count;
    diffuse += is_diffuse_like(c);
    glossy += is_glossy_like(c);
  }
  RAYCOH_HD GroupType type() const {
    return diffuse && glossy ? GroupType::Hybrid
           : diffuse         ? GroupType::Diffuse
           : glossy          ? GroupType::Glossy
                             : GroupType::Independent;
  }
};

// The donor of a group: its d-th diffuse member in row-major order, d uniform in [0, n_diffuse). Defined for
// every n_diffuse: with none or one there is nothing to draw (and no division by zero).
RAYCOH_HD RAYCOH_INLINE uint32_t donor_rank(const GroupingConfig& c, uint32_t group, uint32_t n_diffuse) {
  return n_diffuse <= 1 ? 0u : rng_u32(c.group_seed, c.frame, group, kDimGroupDonor) % n_diffuse;
}

// Finds the donor while the members are offered in row-major order.
struct DonorSearch {
  uint32_t remaining = 0;
  bool found = false;
  uint32_t pixel = 0;
  RAYCOH_HD void offer(MaterialClass c, uint32_t p) {
    if (!found && is_diffuse_like(c) && remaining-- == 0) {
      found = true;
      pixel = p;
    }
  }
};

// Whether a member's own sample votes in the hybrid mean, and its tangent-space direction if it does.
RAYCOH_HD RAYCOH_INLINE bool mean_vote(const ShadingPoint& sp, const DirectionSample& s, Vec3& local) {
  if (!is_glossy_like(sp.cls) || s.flags != kSampleOk) return false;
  local = make_frame(sp.ns).to_local(s.dir);
  return local.z > 0.f;
}

// Sum of the votes, added in the members' row-major order (a float sum is bit-identical only in one order).
struct GlossyMean {
  Vec3 sum{0.f, 0.f, 0.f};
  uint32_t n = 0;
  RAYCOH_HD void add(Vec3 local) {
    sum += local;
    ++n;
  }
};

// The tangent-space direction of a group's diffuse members.
struct SharedDirection {
  Vec3 local;
  bool from_donor = false;       // drawn by the donor (its own ray: one fewer reused ray)
  bool hybrid_fallback = false;  // a hybrid group whose mean nearly cancelled or had no vote
};

// Hybrid groups: the normalised glossy mean, unless it nearly cancels (shorter than 0.01 per vote) or is empty;
// otherwise (and for diffuse groups) the donor's cosine-weighted sample with its own random numbers.
RAYCOH_HD RAYCOH_INLINE SharedDirection shared_direction(const GroupingConfig& c, GroupType type,
                                                         const GlossyMean& mean, uint32_t donor_pixel) {
  SharedDirection d;
  const float len = length(mean.sum);
  if (type == GroupType::Hybrid && mean.n > 0 && len > 1e-2f * static_cast<float>(mean.n) && mean.sum.z > 0.f) {
    d.local = mean.sum * (1.f / len);
    return d;
  }
  d.hybrid_fallback = type == GroupType::Hybrid;
  d.local = sample_cosine_hemisphere(rng_float(c.seed, c.frame, donor_pixel, kDimSecondary0),
                                     rng_float(c.seed, c.frame, donor_pixel, kDimSecondary1));
  d.from_donor = true;
  return d;
}

// A member's ray and its group columns; returns the sample flags.
RAYCOH_HD RAYCOH_INLINE uint32_t write_group_ray(const BatchView& out, size_t slot, const ShadingPoint& sp, uint32_t p,
                                                 const DirectionSample& s, uint32_t t, uint32_t group, GroupType type) {
  const uint32_t flags = write_ray(out, slot, sp, p, s);
  write_group(out, slot, t, group, type);
  return flags;
}

}  // namespace raycoh
