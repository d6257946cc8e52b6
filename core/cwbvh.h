// The compressed 8-wide BVH layout (CWBVH) of Ylitie, Karras & Laine, "Efficient Incoherent Ray Traversal on GPUs
// Through Compressed Wide BVHs" (HPG 2017), shared by every tracer that traverses it (CPU, SIMT model).
//
// A node is 80 bytes (five 16-byte words) and describes up to 8 children in slots 0..7:
//   p, e[3]       the quantisation frame: child boxes are decoded as p + q * 2^(e - 127) per axis, q in [0, 255]
//                 (e is a float's biased exponent byte, so the scale is a power of two and q * scale is exact);
//   imask         bit s set when slot s holds an inner node;
//   child_base    index of the first inner child: the inner children are stored consecutively in slot order, so
//                 slot s's node is child_base + popcount(imask & ((1 << s) - 1));
//   tri_base      index of the first triangle of the leaf children, whose triangles are stored consecutively;
//   meta[s]       0 for an empty slot; an inner child: 0b001'xxxxx with xxxxx = 24 + s; a leaf child: its
//                 triangle count in unary in the top three bits (1 to 3 triangles) and its first triangle's offset
//                 from tri_base (0..23) in the low five bits;
//   qlo/qhi       the children's quantised boxes, rounded outwards so that the decoded box contains the true one.
// Triangles use the BVH2's 48-byte BvhTriangle, so both layouts run the same watertight test.
#pragma once

#include "core/bvh.h"
#include "core/vec.h"

namespace raycoh {

constexpr int kCwbvhWidth = 8;
constexpr int kCwbvhMaxLeafTris = 3;  // the unary count in meta holds at most 3
constexpr int kCwbvhMaxNodeTris = kCwbvhWidth * kCwbvhMaxLeafTris;

struct alignas(16) CwbvhNode {
  Vec3 p;
  uint8_t e[3];
  uint8_t imask;
  uint32_t child_base;
  uint32_t tri_base;
  uint8_t meta[8];
  uint8_t qlo_x[8], qlo_y[8], qlo_z[8];
  uint8_t qhi_x[8], qhi_y[8], qhi_z[8];
};
static_assert(sizeof(CwbvhNode) == 80, "one CWBVH node = five 16-byte words");

struct CwbvhView {
  const CwbvhNode* nodes = nullptr;
  const BvhTriangle* tris = nullptr;
  uint32_t node_count = 0;
  uint32_t tri_count = 0;
};

RAYCOH_HD RAYCOH_INLINE uint32_t popcount32(uint32_t x) {
#if defined(__CUDA_ARCH__)
  return static_cast<uint32_t>(__popc(x));
#else
  return static_cast<uint32_t>(__builtin_popcount(x));
#endif
}
// Index of the lowest set bit; x must not be 0.
RAYCOH_HD RAYCOH_INLINE uint32_t lowest_bit(uint32_t x) {
#if defined(__CUDA_ARCH__)
  return static_cast<uint32_t>(__ffs(static_cast<int>(x)) - 1);
#else
  return static_cast<uint32_t>(__builtin_ctz(x));
#endif
}

// 2^(e - 127) for a biased exponent byte e in [1, 254].
RAYCOH_HD RAYCOH_INLINE float cwbvh_scale(uint8_t e) {
#if defined(__CUDA_ARCH__)
  return __int_as_float(static_cast<int>(e) << 23);
#else
  return __builtin_bit_cast(float, static_cast<int32_t>(e) << 23);
#endif
}

RAYCOH_HD RAYCOH_INLINE bool cwbvh_slot_is_inner(const CwbvhNode& n, int slot) { return (n.imask >> slot) & 1u; }
RAYCOH_HD RAYCOH_INLINE bool cwbvh_slot_is_empty(const CwbvhNode& n, int slot) { return n.meta[slot] == 0; }
RAYCOH_HD RAYCOH_INLINE uint32_t cwbvh_leaf_offset(uint8_t meta) { return meta & 31u; }
RAYCOH_HD RAYCOH_INLINE uint32_t cwbvh_leaf_count(uint8_t meta) { return popcount32(meta >> 5); }
RAYCOH_HD RAYCOH_INLINE uint8_t cwbvh_leaf_meta(uint32_t offset, uint32_t count) {
  return static_cast<uint8_t>((((1u << count) - 1u) << 5) | offset);
}
RAYCOH_HD RAYCOH_INLINE uint8_t cwbvh_inner_meta(int slot) { return static_cast<uint8_t>((1u << 5) | (24u + slot)); }
// Node index of the inner child in `slot`.
RAYCOH_HD RAYCOH_INLINE uint32_t cwbvh_child_index(uint32_t child_base, uint32_t imask, uint32_t slot) {
  return child_base + popcount32(imask & ((1u << slot) - 1u));
}

// The decoded (conservative) box of the child in `slot`.
RAYCOH_HD RAYCOH_INLINE void cwbvh_child_box(const CwbvhNode& n, int slot, Vec3& lo, Vec3& hi) {
  const float sx = cwbvh_scale(n.e[0]), sy = cwbvh_scale(n.e[1]), sz = cwbvh_scale(n.e[2]);
  lo = {n.p.x + static_cast<float>(n.qlo_x[slot]) * sx, n.p.y + static_cast<float>(n.qlo_y[slot]) * sy,
        n.p.z + static_cast<float>(n.qlo_z[slot]) * sz};
  hi = {n.p.x + static_cast<float>(n.qhi_x[slot]) * sx, n.p.y + static_cast<float>(n.qhi_y[slot]) * sy,
        n.p.z + static_cast<float>(n.qhi_z[slot]) * sz};
}

}  // namespace raycoh
