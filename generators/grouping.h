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
#include "generators/shared_sample.h"

namespace raycoh {

// How the diffuse members of a hybrid group get their direction (`ours:hybrid=...`, tangent_reuse.cpp).
enum class HybridRule : uint8_t {
  Paper,        // the normalised mean of the glossy members' directions, weighed as if cosine drawn (biased)
  Donor,        // as in a diffuse group: the donor's cosine sample (unbiased)
  Glossy,       // one glossy member's direction, weight f cos / p of the glossy pdf that drew it (unbiased)
  Independent,  // every diffuse member samples its own lobe, as NoOpt (unbiased, no reuse)
};
// How a direction is carried from one member to another (`ours:frame=...`).
enum class ReuseFrame : uint8_t {
  Duff,    // the same tangent-space coordinates in every member's make_frame(ns) (the paper's; seam at n.z = 0)
  Rotate,  // the minimal rotation from the group's reference normal (its donor's) to the member's normal
};

// One frame's grouping, as both loops read it.
struct GroupingConfig {
  uint32_t seed = 0;        // the run's seed: every pixel's own random numbers
  uint32_t group_seed = 0;  // seed ^ hash32(salt): shuffle constants and donors
  uint32_t frame = 0;
  uint32_t k = 8;                     // group size K
  uint32_t groups_per_full_tile = 8;  // ceil(W H / K): group ids are tile * this + group in tile
  bool interleaved = true;            // ours: shuffled groups; contiguous: group = i / K
  RayOrder order = RayOrder::Tile;    // batch order (core/tile_grid.h)
  HybridRule hybrid = HybridRule::Paper;
  ReuseFrame reuse_frame = ReuseFrame::Duff;
};

// What a device needs to make a generator's batch itself, typed (never its parameter text): Generator::
// device_recipe(). NoOpt: its tile and order (scanline order: one-row tiles); SharedSample (sadeghi, microjitter):
// the same, and its sharing (generators/shared_sample.h); Grouping (ours, contiguous): its tile and its grouping, of
// which config() gives one frame's. Kind None: no device version (the device pipeline refuses it in one line).
struct DeviceRecipe {
  enum class Kind { None, NoOpt, SharedSample, Grouping };
  Kind kind = Kind::None;
  int tile_w = 0, tile_h = 0;
  RayOrder order = RayOrder::Tile;
  GroupingConfig grouping{};    // seed, group_seed and frame are config()'s
  uint32_t salt_hash = 0;       // group_seed = seed ^ salt_hash
  SharedSampleConfig shared{};  // SharedSample: sharing, interleave, radius
  // The grouping of one frame, as the CPU loop and the device kernels read it.
  GroupingConfig config(uint32_t seed, uint32_t frame) const {
    GroupingConfig c = grouping;
    c.seed = seed;
    c.group_seed = seed ^ salt_hash;
    c.frame = frame;
    return c;
  }
};

// A group's shared coordinates of a direction. Duff: tangent-space coordinates in the member's own frame
// (normal = +z). Rotate: the world direction rotated from the member's normal n to the reference normal ref
// (the donor's), so the coordinates are world coordinates around ref. from_shared() is the inverse for a member.
RAYCOH_HD RAYCOH_INLINE Vec3 to_shared(const GroupingConfig& c, Vec3 n, Vec3 ref, Vec3 w) {
  return c.reuse_frame == ReuseFrame::Rotate ? rotate_between(n, ref, w) : make_frame(n).to_local(w);
}
RAYCOH_HD RAYCOH_INLINE Vec3 from_shared(const GroupingConfig& c, Vec3 n, Vec3 ref, Vec3 v) {
  return c.reuse_frame == ReuseFrame::Rotate ? rotate_between(ref, n, v) : make_frame(n).to_world(v);
}
// The cosine of shared coordinates v to the normal (the same for every member: both frames preserve it).
RAYCOH_HD RAYCOH_INLINE float shared_cos(const GroupingConfig& c, Vec3 ref, Vec3 v) {
  return c.reuse_frame == ReuseFrame::Rotate ? dot(v, ref) : v.z;
}

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

// The rank among a hybrid group's glossy members (row-major) of the one whose direction hybrid=glossy reuses,
// uniform and independent of the samples.
RAYCOH_HD RAYCOH_INLINE uint32_t glossy_rank(const GroupingConfig& c, uint32_t group, uint32_t n_glossy) {
  return n_glossy <= 1 ? 0u : rng_u32(c.group_seed, c.frame, group, kDimGroupGlossy) % n_glossy;
}

// Whether a member's own sample votes in the hybrid mean, and its shared coordinates if it does (ref: the
// group's reference normal, read by frame=rotate only).
RAYCOH_HD RAYCOH_INLINE bool mean_vote(const GroupingConfig& c, const ShadingPoint& sp, const DirectionSample& s,
                                       Vec3 ref, Vec3& local) {
  if (!is_glossy_like(sp.cls) || s.flags != kSampleOk) return false;
  local = to_shared(c, sp.ns, ref, s.dir);
  return shared_cos(c, ref, local) > 0.f;
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

// The direction of a group's diffuse members, in shared coordinates.
struct SharedDirection {
  Vec3 local;
  float glossy_pdf = 0.f;        // hybrid=glossy: pdf of the reused glossy sample (0: none usable, weight 0)
  bool from_donor = false;       // drawn by the donor (its own ray: one fewer reused ray)
  bool hybrid_fallback = false;  // hybrid=paper: a hybrid group whose mean nearly cancelled or had no vote
};

// hybrid=paper, hybrid groups: the normalised glossy mean, unless it nearly cancels (shorter than 0.01 per vote)
// or is empty; otherwise (and for diffuse groups, and hybrid=donor) the donor's cosine-weighted sample with its
// own random numbers (ref: the donor's normal). hybrid=glossy takes glossy_direction() instead.
RAYCOH_HD RAYCOH_INLINE SharedDirection shared_direction(const GroupingConfig& c, GroupType type,
                                                         const GlossyMean& mean, uint32_t donor_pixel, Vec3 ref) {
  SharedDirection d;
  if (type == GroupType::Hybrid && c.hybrid == HybridRule::Paper) {
    const float len = length(mean.sum);
    if (mean.n > 0 && len > 1e-2f * static_cast<float>(mean.n) && shared_cos(c, ref, mean.sum) > 0.f) {
      d.local = mean.sum * (1.f / len);
      return d;
    }
    d.hybrid_fallback = true;
  }
  const Vec3 local = sample_cosine_hemisphere(rng_float(c.seed, c.frame, donor_pixel, kDimSecondary0),
                                              rng_float(c.seed, c.frame, donor_pixel, kDimSecondary1));
  d.local = c.reuse_frame == ReuseFrame::Rotate ? make_frame(ref).to_world(local) : local;
  d.from_donor = true;
  return d;
}

// hybrid=glossy: the chosen glossy member's own sample s (at sp) in shared coordinates, with the pdf that drew
// it. Usable when it is finite and above that member's shading surface (a sample below it carries no pdf: the
// diffuse members then get weight 0, which keeps the estimate unbiased since the choice is made before sampling).
RAYCOH_HD RAYCOH_INLINE SharedDirection glossy_direction(const GroupingConfig& c, const ShadingPoint& sp,
                                                         const DirectionSample& s, Vec3 ref) {
  SharedDirection d;
  d.local = c.reuse_frame == ReuseFrame::Rotate ? ref : Vec3{0.f, 0.f, 1.f};
  if ((s.flags & (kSampleNonFinite | kSampleBelowShading)) != 0 || !(s.pdf > 0.f)) return d;
  const Vec3 local = to_shared(c, sp.ns, ref, s.dir);
  if (!(shared_cos(c, ref, local) > 0.f)) return d;
  d.local = local;
  d.glossy_pdf = s.pdf;
  return d;
}

// Diffuse member sp (pixel p) of a group of the given type: its direction from the group's shared one d.
// hybrid=glossy: weight f cos / p_glossy (the pdf that drew the direction; rotations and the tangent-space copy
// keep solid angle), while the pdf column stays the member's own cos / pi, the BSDF pdf that next-event estimation
// evaluates, so the first bounce's MIS weights still sum to one.
RAYCOH_HD RAYCOH_INLINE DirectionSample member_direction(const GroupingConfig& c, GroupType type, const BsdfParams& m,
                                                         const ShadingPoint& sp, uint32_t p, Vec3 ref,
                                                         const SharedDirection& d) {
  const bool hybrid = type == GroupType::Hybrid;
  if (hybrid && c.hybrid == HybridRule::Independent) return sample_own_lobe(m, sp, c.seed, c.frame, p);
  DirectionSample s = c.reuse_frame == ReuseFrame::Rotate
                          ? diffuse_from_world(m, sp.ns, sp.ng, from_shared(c, sp.ns, ref, d.local))
                          : diffuse_from_local(m, sp.ns, sp.ng, d.local);
  if (hybrid && c.hybrid == HybridRule::Glossy) {
    if (d.glossy_pdf > 0.f && s.pdf > 0.f) {
      s.weight = s.weight * (s.pdf / d.glossy_pdf);
    } else {
      s.weight = Vec3(0.f);
      s.flags |= kSampleBelowShading;
    }
  }
  return s;
}

// Diffuse members of the group whose ray reuses another member's direction (the reused_rays counter).
RAYCOH_HD RAYCOH_INLINE uint32_t reused_members(const GroupingConfig& c, GroupType type, const SharedDirection& d,
                                                uint32_t n_diffuse) {
  if (type == GroupType::Hybrid && c.hybrid == HybridRule::Independent) return 0;
  return n_diffuse - (d.from_donor ? 1u : 0u);
}

// A member's ray and its group columns; returns the sample flags.
RAYCOH_HD RAYCOH_INLINE uint32_t write_group_ray(const BatchView& out, size_t slot, const ShadingPoint& sp, uint32_t p,
                                                 const DirectionSample& s, uint32_t t, uint32_t group, GroupType type) {
  const uint32_t flags = write_ray(out, slot, sp, p, s);
  write_group(out, slot, t, group, type);
  return flags;
}

}  // namespace raycoh
