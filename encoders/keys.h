// Sort keys of the ray-reordering encoders, one function per encoder, for host and device (docs/design.md section 3).
//
// Every encoder builds a 64-bit code, most significant bit first; a k-bit key is its top k bits
// (key_from_code). Positions are normalised per axis in a box (the scene's bounds),
//     u = clamp((p - lo) / (hi - lo), 0, 1)          a zero-extent axis maps to 0,
// and quantised with b bits as q = min(floor(u 2^b), 2^b - 1). Directions are unit vectors; spherical
// coordinates are phi = atan2(d.y, d.x) / 2pi + 0.5 and theta = acos(clamp(d.z, -1, 1)) / pi, quantised the
// same way. Interleavings put the first-named component in the most significant bit of each level.
//
//   origin_code    3-D Morton code of the origin, 21 bits per axis (x y z per level), left-aligned: bit 0 is 0.
//   reis_code      the top 22 bits of origin_code, then phi and theta interleaved, 21 bits each (phi first)
//                  (Reis et al. 2017, "Coherent Ray-Space Hierarchy via Ray Hashing and Sorting").
//   costa_code     phi and theta interleaved, 4 bits each (phi first), then the origin Morton code with 15 bits
//                  per axis; the 11 low bits are 0 (Costa et al. 2015, "Accelerating Occlusion Rendering on a
//                  GPU via Ray Classification").
//   aila_code      AilaCompact: origin 13 bits per axis, direction (d + 1) / 2 13 bits per axis; the origin's
//                  three top levels alone (o12 o11 o10, x y z each), then 3-bit groups alternating origin and
//                  direction levels o9 d12 o8 d11 ... o0 d3, then d2 d1 d0; the top 64 of these 78 bits
//                  (Aila & Karras 2010, "Architecture Considerations for Tracing Incoherent Rays").
//   twopoint_code  6-D Morton code (ax ay az bx by bz per level) of the origin a and an estimated end point
//                  b = o + L d, L = min(length_factor x longest box extent, tmax, distance to the box's exit),
//                  13 bits per axis each; the top 64 of 78 bits.
//   mlhcc_code     hierarchy cut code (Xiang et al. 2023) in BVH cuts; see encoders/mlhcc.cpp for the rule.
// Meister et al. 2020 ("On Ray Reordering Techniques for Faster GPU Ray Tracing") compare all of these.
//
// Bad input has a defined key and never traps: NaN coordinates quantise to 0, +Inf to 2^b - 1, -Inf to 0; an
// empty or infinite box quantises everything to 0. A zero of either sign in d.x or d.y is read as +0, so the
// poles (0, 0, +-1) have phi = 0.5 and the seam along -x has phi = 1 (q = 2^b - 1) whatever the zero's sign.
//
// Bit-exactness between CPU and GPU: all arithmetic here is IEEE add, subtract, multiply and divide (correctly
// rounded on both sides, with no FMA contraction: -ffp-contract=off / --fmad=false) plus exact integer bit work.
// The one exception is atan2f/acosf for phi and theta: glibc and CUDA (2 ulp documented for both) may differ by
// an ulp or two, which moves a key only when phi or theta lies that close to a quantisation boundary (reis,
// costa). The tests pin the CPU values. Device code must not be built with --use_fast_math.
#pragma once

#include "core/bvh.h"
#include "core/vec.h"

#if !defined(__CUDACC__)
#include <cmath>
#endif

namespace raycoh {

constexpr float kKeyPi = 3.14159265358979323846f;
constexpr float kKeyTwoPi = 6.28318530717958647692f;  // exactly 2 x kKeyPi in float

// Bits per axis of each encoder's quantisation (fixed by the recipes above).
constexpr int kOriginAxisBits = 21;
constexpr int kReisOriginBits = 22;
constexpr int kReisAngleBits = 21;
constexpr int kCostaAngleBits = 4;
constexpr int kCostaOriginAxisBits = 15;
constexpr int kAilaAxisBits = 13;
constexpr int kTwoPointAxisBits = 13;

// ---- normalisation and quantisation -------------------------------------------------------------------------

// (p - lo) / (hi - lo) clamped to [0, 1]; 0 for a zero-extent (or empty, NaN, infinite) axis and for NaN p.
RAYCOH_HD RAYCOH_INLINE float unit_coordinate(float p, float lo, float hi) {
  const float extent = hi - lo;
  if (!(extent > 0.f) || !(extent < __builtin_huge_valf())) return 0.f;
  const float u = (p - lo) / extent;
  if (!(u > 0.f)) return 0.f;  // also NaN
  return u < 1.f ? u : 1.f;
}

// min(floor(u 2^bits), 2^bits - 1) for u in [0, 1]; bits in [1, 31]. Scaling by 2^bits is exact in float, so
// the truncating conversion is the floor of the exact product.
RAYCOH_HD RAYCOH_INLINE uint32_t quantize_unit(float u, int bits) {
  const uint32_t top = (1u << bits) - 1u;
  if (!(u > 0.f)) return 0u;
  if (u >= 1.f) return top;
  const auto q = static_cast<uint32_t>(u * static_cast<float>(1u << bits));
  return q < top ? q : top;
}

RAYCOH_HD RAYCOH_INLINE uint32_t quantize_coordinate(float p, float lo, float hi, int bits) {
  return quantize_unit(unit_coordinate(p, lo, hi), bits);
}

struct QuantizedPoint {
  uint32_t x = 0, y = 0, z = 0;
};

RAYCOH_HD RAYCOH_INLINE QuantizedPoint quantize_point(Vec3 p, const Bounds& box, int bits) {
  return {quantize_coordinate(p.x, box.lo.x, box.hi.x, bits), quantize_coordinate(p.y, box.lo.y, box.hi.y, bits),
          quantize_coordinate(p.z, box.lo.z, box.hi.z, bits)};
}

// Unit direction component d in [-1, 1] as (d + 1) / 2, quantised (AilaCompact).
RAYCOH_HD RAYCOH_INLINE QuantizedPoint quantize_direction(Vec3 d, int bits) {
  return {quantize_coordinate(d.x, -1.f, 1.f, bits), quantize_coordinate(d.y, -1.f, 1.f, bits),
          quantize_coordinate(d.z, -1.f, 1.f, bits)};
}

// phi = atan2(d.y, d.x) / 2pi + 0.5 in [0, 1]. Adding +0 turns -0 into +0 (IEEE round-to-nearest), which pins
// the seam and the poles; compilers keep it because they may not assume the sign of zero away.
RAYCOH_HD RAYCOH_INLINE float spherical_phi(Vec3 d) {
  const float x = d.x + 0.f;
  const float y = d.y + 0.f;
  return atan2f(y, x) / kKeyTwoPi + 0.5f;
}

// theta = acos(clamp(d.z, -1, 1)) / pi in [0, 1]; NaN stays NaN and quantises to 0.
RAYCOH_HD RAYCOH_INLINE float spherical_theta(Vec3 d) {
  const float z = d.z < -1.f ? -1.f : (d.z > 1.f ? 1.f : d.z);
  return acosf(z) / kKeyPi;
}

// ---- bit interleaving ---------------------------------------------------------------------------------------

// Bit i of the low 21 bits of v moves to bit 3i (the classic shift-and-mask spread for 3-D Morton codes).
RAYCOH_HD RAYCOH_INLINE uint64_t spread_bits_3(uint32_t v) {
  uint64_t x = v & 0x1FFFFFu;
  x = (x | (x << 32)) & 0x001F00000000FFFFull;
  x = (x | (x << 16)) & 0x001F0000FF0000FFull;
  x = (x | (x << 8)) & 0x100F00F00F00F00Full;
  x = (x | (x << 4)) & 0x10C30C30C30C30C3ull;
  x = (x | (x << 2)) & 0x1249249249249249ull;
  return x;
}

// Bit i of v moves to bit 2i.
RAYCOH_HD RAYCOH_INLINE uint64_t spread_bits_2(uint32_t v) {
  uint64_t x = v;
  x = (x | (x << 16)) & 0x0000FFFF0000FFFFull;
  x = (x | (x << 8)) & 0x00FF00FF00FF00FFull;
  x = (x | (x << 4)) & 0x0F0F0F0F0F0F0F0Full;
  x = (x | (x << 2)) & 0x3333333333333333ull;
  x = (x | (x << 1)) & 0x5555555555555555ull;
  return x;
}

// 3-D Morton code of up to 21 bits per axis, x in the most significant bit of each level; 3 x bits wide.
RAYCOH_HD RAYCOH_INLINE uint64_t morton3(QuantizedPoint q) {
  return (spread_bits_3(q.x) << 2) | (spread_bits_3(q.y) << 1) | spread_bits_3(q.z);
}

// 2-D Morton code of up to 32 bits per component, a in the more significant bit of each level.
RAYCOH_HD RAYCOH_INLINE uint64_t morton2(uint32_t a, uint32_t b) { return (spread_bits_2(a) << 1) | spread_bits_2(b); }

// Appends fields to a 64-bit code from the most significant bit down; what falls past bit 0 is dropped, which is
// how the longer recipes are "truncated to 64 bits".
struct CodeWriter {
  uint64_t code = 0;
  int used = 0;  // bits written so far, counted from the MSB (may exceed 64)
  RAYCOH_HD void put(uint64_t value, int width) {
    if (used < 64 && width > 0) {
      const int shift = 64 - used - width;
      code |= shift >= 0 ? value << shift : value >> (-shift);
    }
    used += width;
  }
};

// Level l (3 bits, x y z) of a 3-D Morton code.
RAYCOH_HD RAYCOH_INLINE uint64_t morton_level(uint64_t morton, int level) { return (morton >> (3 * level)) & 7u; }

// The k-bit key of a code: its top k bits, k in [1, 64].
RAYCOH_HD RAYCOH_INLINE uint64_t key_from_code(uint64_t code, int key_bits) {
  return key_bits >= 64 ? code : code >> (64 - key_bits);
}

// ---- the encoders' codes ------------------------------------------------------------------------------------

RAYCOH_HD RAYCOH_INLINE uint64_t origin_code(Vec3 org, const Bounds& box) {
  return morton3(quantize_point(org, box, kOriginAxisBits)) << 1;
}

RAYCOH_HD RAYCOH_INLINE uint64_t reis_code(Vec3 org, Vec3 dir, const Bounds& box) {
  constexpr int kAngleShift = 64 - kReisOriginBits;  // the 42 low bits hold the direction
  const uint64_t origin_part = (origin_code(org, box) >> kAngleShift) << kAngleShift;
  const uint32_t phi = quantize_unit(spherical_phi(dir), kReisAngleBits);
  const uint32_t theta = quantize_unit(spherical_theta(dir), kReisAngleBits);
  return origin_part | morton2(phi, theta);
}

RAYCOH_HD RAYCOH_INLINE uint64_t costa_code(Vec3 org, Vec3 dir, const Bounds& box) {
  const uint32_t phi = quantize_unit(spherical_phi(dir), kCostaAngleBits);
  const uint32_t theta = quantize_unit(spherical_theta(dir), kCostaAngleBits);
  const uint64_t origin = morton3(quantize_point(org, box, kCostaOriginAxisBits));  // 45 bits
  return (morton2(phi, theta) << 56) | (origin << 11);
}

RAYCOH_HD RAYCOH_INLINE uint64_t aila_code(Vec3 org, Vec3 dir, const Bounds& box) {
  const uint64_t o = morton3(quantize_point(org, box, kAilaAxisBits));
  const uint64_t d = morton3(quantize_direction(dir, kAilaAxisBits));
  CodeWriter w;
  for (int level = kAilaAxisBits - 1; level >= kAilaAxisBits - 3; --level) w.put(morton_level(o, level), 3);
  for (int level = kAilaAxisBits - 4; level >= 0 && w.used < 64; --level) {
    w.put(morton_level(o, level), 3);
    w.put(morton_level(d, level + 3), 3);
  }
  return w.code;  // d2 d1 d0 would follow 69 bits from the MSB: past the 64 kept
}

// Length of the estimated segment: min(length_factor x longest extent of box, tmax, distance to the box's exit
// along dir), never negative. A NaN candidate (NaN tmax, a NaN coordinate) is skipped, as no comparison with it
// holds; a broken box gives 0, and so does an origin past the box's far side.
RAYCOH_HD RAYCOH_INLINE float estimated_length(Vec3 org, Vec3 dir, float tmax, const Bounds& box, float length_factor) {
  const Vec3 extent = box.extent();
  float length = length_factor * max_f(extent.x, max_f(extent.y, extent.z));
  if (tmax < length) length = tmax;
  for (int axis = 0; axis < 3; ++axis) {
    const float d = dir[axis];
    const float exit = d > 0.f ? (box.hi[axis] - org[axis]) / d : (d < 0.f ? (box.lo[axis] - org[axis]) / d : length);
    if (exit < length) length = exit;
  }
  return length > 0.f ? length : 0.f;
}

RAYCOH_HD RAYCOH_INLINE Vec3 estimated_end_point(Vec3 org, Vec3 dir, float tmax, const Bounds& box,
                                                 float length_factor) {
  const float length = estimated_length(org, dir, tmax, box, length_factor);
  return {org.x + dir.x * length, org.y + dir.y * length, org.z + dir.z * length};
}

RAYCOH_HD RAYCOH_INLINE uint64_t twopoint_code(Vec3 org, Vec3 dir, float tmax, const Bounds& box, float length_factor) {
  const uint64_t a = morton3(quantize_point(org, box, kTwoPointAxisBits));
  const uint64_t b =
      morton3(quantize_point(estimated_end_point(org, dir, tmax, box, length_factor), box, kTwoPointAxisBits));
  CodeWriter w;
  for (int level = kTwoPointAxisBits - 1; level >= 0 && w.used < 64; --level) {
    w.put(morton_level(a, level), 3);
    w.put(morton_level(b, level), 3);
  }
  return w.code;
}

// ---- MLHCC: hierarchy cut code ------------------------------------------------------------------------------

// Cut membership of the two children of one BVH node: level[c] = 0 when child c is in no cut, else the (1-based)
// cut level it belongs to, and rank[c] its number within that level (see encoders/mlhcc.cpp).
struct MlhccNodeCut {
  uint32_t rank[2] = {0, 0};
  uint32_t level[2] = {0, 0};
};
static_assert(sizeof(MlhccNodeCut) == 16, "one 16-byte word per node");

constexpr int kMlhccMaxLevels = kTraversalStackSize;  // a cut level is at least one tree level deeper

// Non-owning view of the cuts of one BVH, valid on whichever side the arrays live (built on the host by
// build_mlhcc_cuts in encoders/mlhcc_cuts.h). level_bits[l] and level_offset[l] describe cut level l + 1.
struct MlhccCuts {
  const BvhNode* nodes = nullptr;      // the BVH's nodes: point location uses the children's boxes
  const MlhccNodeCut* cuts = nullptr;  // one per node, same index
  uint32_t node_count = 0;
  uint32_t level_count = 0;
  uint16_t level_bits[kMlhccMaxLevels] = {};    // bits of a rank at that level
  uint16_t level_offset[kMlhccMaxLevels] = {};  // sum of level_bits of the levels above
};

// Squared distance from p to a box (0 inside); +Inf for an empty box.
RAYCOH_HD RAYCOH_INLINE float squared_distance(Vec3 p, Vec3 lo, Vec3 hi) {
  float s = 0.f;
  for (int axis = 0; axis < 3; ++axis) {
    const float d = max_f(max_f(lo[axis] - p[axis], p[axis] - hi[axis]), 0.f);
    s = s + d * d;
  }
  return s;
}

// Which child of an inner node a point belongs to: the nearer box (distance 0 inside); when both are equally
// near (the point is in both, or in neither at equal distance) the smaller box, then child 0.
RAYCOH_HD RAYCOH_INLINE int locate_child(const BvhNode& node, Vec3 p) {
  const float d0 = squared_distance(p, node.lo0, node.hi0);
  const float d1 = squared_distance(p, node.lo1, node.hi1);
  if (d0 < d1) return 0;
  if (d1 < d0) return 1;
  const float a0 = Bounds{node.lo0, node.hi0}.half_area();
  const float a1 = Bounds{node.lo1, node.hi1}.half_area();
  return a1 < a0 ? 1 : 0;
}

// Clamps p into the box; NaN goes to lo, so point location never compares NaN.
RAYCOH_HD RAYCOH_INLINE Vec3 clamp_to_box(Vec3 p, const Bounds& box) {
  Vec3 out;
  for (int axis = 0; axis < 3; ++axis) {
    const float v = p[axis];
    out[axis] = !(v > box.lo[axis]) ? box.lo[axis] : (v > box.hi[axis] ? box.hi[axis] : v);
  }
  return out;
}

// Descends from the root to the leaf that holds p and writes the rank of every cut node on the way into the
// code: the rank at level l goes to bit offset (field_stride x level_offset[l] + field_index x level_bits[l])
// from the MSB, so that with the end point (stride 2) origin and end point alternate level by level. The
// descent stops at the first level that starts at or past bit offset `needed_bits`. on_iteration(node) runs as
// each iteration starts, with the index of the node it reads: the key kernel's does nothing (its SASS is the
// loop's alone, the stage model's instruction count); bench/mlhcc_walks.cpp counts the walk's trips with it and
// names the loads each iteration makes (bench/mlhcc_key_l1.h record_walk).
struct MlhccNoCount {
  RAYCOH_HD RAYCOH_INLINE void operator()(int32_t) const {}
};
template <class OnIteration = MlhccNoCount>
RAYCOH_HD RAYCOH_INLINE void mlhcc_write_path(const MlhccCuts& cuts, Vec3 p, int field_stride, int field_index,
                                              int needed_bits, uint64_t& code, OnIteration on_iteration = {}) {
  if (cuts.node_count == 0) return;
  int32_t node = 0;
  for (int depth = 0; depth < kMlhccMaxLevels; ++depth) {
    on_iteration(node);
    const BvhNode& n = cuts.nodes[node];
    const int c = locate_child(n, p);
    const uint32_t level = cuts.cuts[node].level[c];
    if (level > 0) {
      const int width = cuts.level_bits[level - 1];
      const int offset = field_stride * cuts.level_offset[level - 1] + field_index * width;
      if (offset >= needed_bits) return;  // every deeper level lies further right
      CodeWriter w{code, offset};
      w.put(cuts.cuts[node].rank[c], width);
      code = w.code;
    }
    const int32_t child = n.child[c];
    if (is_leaf_ref(child)) return;
    node = child;
  }
}

// MLHCC code of a ray: per cut level, the origin's rank then (with_end) the estimated end point's rank. Only
// the top key_bits bits are computed (the descent stops there, which is most of its cost); the rest stay 0.
RAYCOH_HD RAYCOH_INLINE uint64_t mlhcc_code(Vec3 org, Vec3 dir, float tmax, const Bounds& box, float length_factor,
                                            const MlhccCuts& cuts, bool with_end, int key_bits = 64) {
  uint64_t code = 0;
  const int stride = with_end ? 2 : 1;
  mlhcc_write_path(cuts, clamp_to_box(org, box), stride, 0, key_bits, code);
  if (with_end) {
    const Vec3 end = clamp_to_box(estimated_end_point(org, dir, tmax, box, length_factor), box);
    mlhcc_write_path(cuts, end, stride, 1, key_bits, code);
  }
  return code;
}

}  // namespace raycoh
