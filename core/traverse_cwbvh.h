// Closest-hit traversal of the compressed 8-wide BVH (core/cwbvh.h), written once for host and device.
//
// After Ylitie, Karras & Laine (HPG 2017), in our own formulation:
//   - The ray keeps a *node group* (an inner node's child_base, imask and the bits of the children it hit, not yet
//     visited) and a *triangle group* (tri_base and a bit per triangle of the leaves it hit). The stack holds node
//     groups, 8 bytes each; a node step pushes at most one, so the stack is never deeper than the tree.
//   - Octant-ordered traversal: the builder puts in slot s the child that rays travelling towards octant s should
//     visit first (bvh/cwbvh_build.cpp); a ray of octant o (bit k set when dir[k] < 0) keeps the hit of slot s in
//     bit s ^ o and always takes the lowest bit, so it visits slots in the order o, o ^ 1, ..., o ^ 7: near to far
//     without sorting, as in the paper.
//   - As in the paper, the ray is transformed into each node's quantised frame and each child plane costs one FMA;
//     ours rounds it outwards (entry planes down, exit planes up), so the quantised boxes, which contain the true
//     ones, cannot lose a hit. The triangle test is the BVH2's.
// The loop bodies are exposed as cwbvh_node_step() and cwbvh_triangle_step() so that the SIMT model can step a
// warp in lock step (simt/simt_cwbvh.h); closest_hit_cwbvh() is the scalar driver. A lane with a triangle group
// does its triangles before its next node step, in either driver, so both compute the same hits bit for bit.
// Not modelled from the paper: its compressed stack entries' "triangle group on the stack" case and its
// rotation of the inner-child bits (both performance details of the same visiting order).
#pragma once

#include "core/cwbvh.h"
#include "core/directed_rounding.h"
#include "core/traverse.h"

namespace raycoh {

// Stack: InlineStackOf<uint64_t> (the CPU tracer and the simt model, a state per lane) or StackRefOf<uint64_t>
// (closest_hit_cwbvh: the entries apart, so that on the GPU the state stays in registers; core/traverse.h).
template <class Stack>
struct CwbvhStateOf {
  PreparedRay ray;
  Hit hit;
  uint32_t octant;      // bit k set when dir[k] < 0
  uint32_t node_base;   // node group: child_base
  uint32_t node_hits;   // node group: bit (slot ^ octant) per hit inner child not yet visited (bits 0..7)
  uint32_t node_imask;  // node group: the parent's imask
  uint32_t tri_base;    // triangle group: tri_base
  uint32_t tri_hits;    // triangle group: bit i for triangle tri_base + i not yet tested (bits 0..23)
  int sp;
  Stack stack;  // node groups: base | hits << 32 | imask << 40
};
using CwbvhState = CwbvhStateOf<InlineStackOf<uint64_t>>;

template <class State>
RAYCOH_HD RAYCOH_INLINE void cwbvh_begin(State& s, const Ray& r) {
  s.ray = prepare_ray(r);
  s.hit = Hit{};
  s.hit.t = r.tmax;
  s.octant = (r.dir.x < 0.f ? 1u : 0u) | (r.dir.y < 0.f ? 2u : 0u) | (r.dir.z < 0.f ? 4u : 0u);
  // The root as a group of one: slot 0 of a virtual parent whose only inner child is node 0.
  s.node_base = 0;
  s.node_imask = 1;
  s.node_hits = 1u << (0u ^ s.octant);
  s.tri_base = 0;
  s.tri_hits = 0;
  s.sp = 0;
  if (!(r.tmax > r.tmin) || !is_finite(r.org) || !is_finite(r.dir) || !(dot(r.dir, r.dir) > 0.f)) s.node_hits = 0;
}

template <class State>
RAYCOH_HD RAYCOH_INLINE bool cwbvh_has_triangles(const State& s) {
  return s.tri_hits != 0;
}
template <class State>
RAYCOH_HD RAYCOH_INLINE bool cwbvh_wants_node(const State& s) {
  return s.tri_hits == 0 && (s.node_hits != 0 || s.sp > 0);
}
template <class State>
RAYCOH_HD RAYCOH_INLINE bool cwbvh_done(const State& s) {
  return s.tri_hits == 0 && s.node_hits == 0 && s.sp == 0;
}

// The node the next cwbvh_node_step() fetches (pops a group first when the current one is empty). Requires
// cwbvh_wants_node(s).
template <class State>
RAYCOH_HD RAYCOH_INLINE uint32_t cwbvh_next_node(State& s) {
  if (s.node_hits == 0) {
    const uint64_t g = s.stack[--s.sp];
    s.node_base = static_cast<uint32_t>(g);
    s.node_hits = static_cast<uint32_t>(g >> 32) & 0xFFu;
    s.node_imask = static_cast<uint32_t>(g >> 40) & 0xFFu;
  }
  const uint32_t slot = lowest_bit(s.node_hits) ^ s.octant;
  return cwbvh_child_index(s.node_base, s.node_imask, slot);
}

// A node as the kernel reads it: five 16-byte words (core/cwbvh.h gives the byte layout).
struct alignas(16) CwbvhNodeWords {
  uint32_t w[20];
};
static_assert(sizeof(CwbvhNodeWords) == sizeof(CwbvhNode), "same bytes");

RAYCOH_HD RAYCOH_INLINE float cwbvh_bits_float(uint32_t bits) {
#if defined(__CUDA_ARCH__)
  return __int_as_float(static_cast<int>(bits));
#else
  return __builtin_bit_cast(float, bits);
#endif
}

// Byte k (0..3) of a word as a float, exactly: 2^23 + q has q in its low mantissa bits, and one byte permute
// builds 0x4B0000qq on the device.
RAYCOH_HD RAYCOH_INLINE float cwbvh_byte_float(uint32_t word, int k) {
#if defined(__CUDA_ARCH__)
  const uint32_t bits = __byte_perm(word, 0x4B000000u, static_cast<uint32_t>(k) | 0x7440u);
#else
  const uint32_t bits = 0x4B000000u | ((word >> (8 * k)) & 0xFFu);
#endif
  return cwbvh_bits_float(bits) - 8388608.f;
}

// Bit k set when byte k of a meta word is not 0 (an empty slot): every used slot has one of bits 5..7 set.
RAYCOH_HD RAYCOH_INLINE uint32_t cwbvh_nonempty(uint32_t meta) {
  const uint32_t b = ((((meta >> 5) & 0x07070707u) + 0x07070707u) & 0x08080808u) >> 3;  // bits 0, 8, 16, 24
  return (b | (b >> 7) | (b >> 14) | (b >> 21)) & 0xFu;
}

// Bit slot of `bits` moved to bit slot ^ octant (the order in which a ray of that octant visits the slots).
RAYCOH_HD RAYCOH_INLINE uint32_t cwbvh_octant_order(uint32_t bits, uint32_t octant) {
  if (octant & 1u) bits = ((bits & 0x55u) << 1) | ((bits >> 1) & 0x55u);
  if (octant & 2u) bits = ((bits & 0x33u) << 2) | ((bits >> 2) & 0x33u);
  if (octant & 4u) bits = ((bits & 0x0Fu) << 4) | ((bits >> 4) & 0x0Fu);
  return bits;
}

// The ray in a node's quantised frame, per axis: the distance to the plane q of the axis is t(q) = q * a + b
// with a = scale * inv_dir (exact: the scale is a power of two) and b = (p - org) * inv_dir, kept as a lower and an
// upper bound (directed rounding, core/directed_rounding.h).
struct CwbvhFrame {
  float a, b_down, b_up;
};

RAYCOH_HD RAYCOH_INLINE CwbvhFrame cwbvh_frame(float p, float scale, float org, float inv) {
  const float lo = sub_down(p, org), hi = sub_up(p, org);
  return {scale * inv, mul_down(inv < 0.f ? hi : lo, inv), mul_up(inv < 0.f ? lo : hi, inv)};
}

// One node step: take the nearest unvisited child of the node group, push the rest of the group, fetch the child
// and test its 8 child boxes; the hit inner children become the node group, the hit leaves the triangle group.
// Each plane is one FMA in the node's frame, rounded down for the entry planes and up for the exit planes, so a
// child's [tnear, tfar] contains the exact distances to its decoded box (whose real value contains the child's
// true box: bvh/cwbvh_build.cpp), before the far distance's 1 + 2 gamma(3) that intersect_box() applies too.
template <class Counters, class State>
RAYCOH_HD RAYCOH_INLINE void cwbvh_node_step(State& s, const CwbvhView& bvh, Counters& counters) {
  const uint32_t index = cwbvh_next_node(s);
  s.node_hits &= s.node_hits - 1u;
  if (s.node_hits != 0)
    s.stack[s.sp++] = uint64_t{s.node_base} | (uint64_t{s.node_hits} << 32) | (uint64_t{s.node_imask} << 40);
#if defined(__CUDA_ARCH__)
  const CwbvhNodeWords n = reinterpret_cast<const CwbvhNodeWords*>(bvh.nodes)[index];  // five 16-byte loads
#else
  CwbvhNodeWords n;
  __builtin_memcpy(&n, &bvh.nodes[index], sizeof(n));
#endif
  counters.on_node(static_cast<int32_t>(index));
  const PreparedRay& r = s.ray;
  const CwbvhFrame x =
      cwbvh_frame(cwbvh_bits_float(n.w[0]), cwbvh_bits_float((n.w[3] & 0xFFu) << 23), r.org.x, r.inv_dir.x);
  const CwbvhFrame y =
      cwbvh_frame(cwbvh_bits_float(n.w[1]), cwbvh_bits_float(((n.w[3] >> 8) & 0xFFu) << 23), r.org.y, r.inv_dir.y);
  const CwbvhFrame z =
      cwbvh_frame(cwbvh_bits_float(n.w[2]), cwbvh_bits_float(((n.w[3] >> 16) & 0xFFu) << 23), r.org.z, r.inv_dir.z);
  const uint32_t imask = n.w[3] >> 24;
  // Plane words: qlo_x = w[8..9], qlo_y = w[10..11], qlo_z = w[12..13], qhi_x = w[14..15], qhi_y = w[16..17],
  // qhi_z = w[18..19]; the entry plane of an axis is qlo unless the ray travels towards -axis.
  const bool fx = r.inv_dir.x < 0.f, fy = r.inv_dir.y < 0.f, fz = r.inv_dir.z < 0.f;
  const uint32_t nx0 = fx ? n.w[14] : n.w[8], nx1 = fx ? n.w[15] : n.w[9];
  const uint32_t fx0 = fx ? n.w[8] : n.w[14], fx1 = fx ? n.w[9] : n.w[15];
  const uint32_t ny0 = fy ? n.w[16] : n.w[10], ny1 = fy ? n.w[17] : n.w[11];
  const uint32_t fy0 = fy ? n.w[10] : n.w[16], fy1 = fy ? n.w[11] : n.w[17];
  const uint32_t nz0 = fz ? n.w[18] : n.w[12], nz1 = fz ? n.w[19] : n.w[13];
  const uint32_t fz0 = fz ? n.w[12] : n.w[18], fz1 = fz ? n.w[13] : n.w[19];
  const float tmax = s.hit.t;
  uint32_t box_hits = 0;  // bit slot: the slot's box is hit (empty slots masked below)
#if defined(__CUDA_ARCH__)
#pragma unroll
#endif
  for (int slot = 0; slot < kCwbvhWidth; ++slot) {
    const bool h = slot >= 4;
    const int k = slot & 3;
    const float tx0 = fma_down(cwbvh_byte_float(h ? nx1 : nx0, k), x.a, x.b_down);
    const float tx1 = fma_up(cwbvh_byte_float(h ? fx1 : fx0, k), x.a, x.b_up);
    const float ty0 = fma_down(cwbvh_byte_float(h ? ny1 : ny0, k), y.a, y.b_down);
    const float ty1 = fma_up(cwbvh_byte_float(h ? fy1 : fy0, k), y.a, y.b_up);
    const float tz0 = fma_down(cwbvh_byte_float(h ? nz1 : nz0, k), z.a, z.b_down);
    const float tz1 = fma_up(cwbvh_byte_float(h ? fz1 : fz0, k), z.a, z.b_up);
    // fminf/fmaxf (one instruction each on the device): no operand is NaN, so they choose as max_f/min_f do
    // except between +0 and -0, which compare equal below.
    const float tnear = fmaxf(fmaxf(tx0, ty0), fmaxf(tz0, r.tmin));
    const float tfar = fminf(fminf(tx1, ty1), fminf(tz1, tmax)) * 1.00000024f;  // as intersect_box()
    box_hits |= (tnear <= tfar ? 1u : 0u) << slot;
  }
  box_hits &= cwbvh_nonempty(n.w[6]) | (cwbvh_nonempty(n.w[7]) << 4);
  s.node_base = n.w[4];
  s.node_imask = imask;
  s.node_hits = cwbvh_octant_order(box_hits & imask, s.octant);
  s.tri_base = n.w[5];
  uint32_t tri_hits = 0;
  for (uint32_t leaves = box_hits & ~imask; leaves != 0; leaves &= leaves - 1u) {
    const uint32_t slot = lowest_bit(leaves);
    const uint32_t meta = ((slot >= 4 ? n.w[7] : n.w[6]) >> (8 * (slot & 3u))) & 0xFFu;  // no indexed array
    tri_hits |= (meta >> 5) << (meta & 31u);  // the unary count is the leaf's triangle mask
  }
  s.tri_hits = tri_hits;
}

// One triangle of the triangle group, read as three 16-byte words (load_triangle_wide, core/bvh.h).
template <class Counters, class Filter = NoAlphaTest, class State>
RAYCOH_HD RAYCOH_INLINE void cwbvh_triangle_step(State& s, const CwbvhView& bvh, Counters& counters,
                                                 const Filter& filter = Filter{}) {
  const uint32_t i = s.tri_base + lowest_bit(s.tri_hits);
  s.tri_hits &= s.tri_hits - 1u;
  counters.on_triangle(i);
  intersect_triangle(s.ray, load_triangle_wide(bvh.tris, i), s.hit, filter);
}

// The loop of one ray from cwbvh_begin to its end, on a state whose stack the caller placed.
template <class State, class Counters, class Filter>
RAYCOH_HD RAYCOH_INLINE void cwbvh_traverse(State& s, const CwbvhView& bvh, Counters& counters, const Filter& filter) {
  while (!cwbvh_done(s)) {
    if (cwbvh_has_triangles(s)) {
      counters.on_leaf(0);
      while (cwbvh_has_triangles(s)) cwbvh_triangle_step(s, bvh, counters, filter);
    } else {
      cwbvh_node_step(s, bvh, counters);
    }
  }
}

// Scalar driver: closest hit of one ray (with alpha cut-outs when Filter is AlphaTest, core/alpha_mask.h). The
// stack is apart from the state (StackRefOf), so that on the GPU only the stack is in local memory.
template <class Counters, class Filter = NoAlphaTest>
RAYCOH_HD RAYCOH_INLINE Hit closest_hit_cwbvh(const CwbvhView& bvh, const Ray& r, Counters& counters,
                                              const Filter& filter = Filter{}) {
  uint64_t entries[kTraversalStackSize];
  CwbvhStateOf<StackRefOf<uint64_t>> s;
  s.stack.entry = entries;
  cwbvh_begin(s, r);
  cwbvh_traverse(s, bvh, counters, filter);
  return s.hit;
}

RAYCOH_HD RAYCOH_INLINE Hit closest_hit_cwbvh(const CwbvhView& bvh, const Ray& r) {
  NoCounters none;
  return closest_hit_cwbvh(bvh, r, none);
}

}  // namespace raycoh
