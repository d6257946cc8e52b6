// The flat BVH2 layout shared by every tracer that uses our traversal (CPU, SIMT model, CUDA).
//
// Following Aila & Laine ("Understanding the Efficiency of Ray Traversal on GPUs", HPG 2009), a node stores the
// boxes of *both* children, so one 64-byte fetch (one cache line) decides which children a ray enters.
// A child reference is an int32:
//   ref >= 0            an inner node index,
//   ref <  0            a leaf: ~ref = (first << kLeafCountBits) | count, triangles tris[first .. first+count),
//   kSentinel           the bottom of the traversal stack (positive, never a valid node index).
// Triangles are stored in leaf order, 48 bytes each, with the scene's primitive id in the spare word.
#pragma once

#include <cstddef>

#include "core/vec.h"

namespace raycoh {

constexpr int kLeafCountBits = 5;
constexpr int kMaxLeafSize = (1 << kLeafCountBits) - 1;  // 31
constexpr uint32_t kMaxLeafFirst = (1u << (31 - kLeafCountBits)) - 1;
constexpr int32_t kSentinel = 0x7FFFFFFF;
constexpr int kTraversalStackSize = 64;

struct alignas(16) BvhNode {
  Vec3 lo0, hi0;  // child 0 box
  Vec3 lo1, hi1;  // child 1 box
  int32_t child[2];
  uint32_t pad[2];
};
static_assert(sizeof(BvhNode) == 64, "one node = one 64-byte cache line");

struct alignas(16) BvhTriangle {
  Vec3 v0;
  uint32_t prim;  // triangle index in the scene
  Vec3 v1;
  uint32_t pad0;
  Vec3 v2;
  uint32_t pad1;
};
static_assert(sizeof(BvhTriangle) == 48, "triangle = three 16-byte words");
static_assert(offsetof(BvhNode, child) == 48 && offsetof(BvhTriangle, prim) == 12 && offsetof(BvhTriangle, v2) == 32,
              "load_node_wide / load_triangle_wide read the fields at these offsets");

RAYCOH_HD RAYCOH_INLINE bool is_leaf_ref(int32_t ref) { return ref < 0; }
RAYCOH_HD RAYCOH_INLINE int32_t make_leaf_ref(uint32_t first, uint32_t count) {
  return ~static_cast<int32_t>((first << kLeafCountBits) | count);
}
RAYCOH_HD RAYCOH_INLINE uint32_t leaf_first(int32_t ref) { return static_cast<uint32_t>(~ref) >> kLeafCountBits; }
RAYCOH_HD RAYCOH_INLINE uint32_t leaf_count(int32_t ref) {
  return static_cast<uint32_t>(~ref) & static_cast<uint32_t>(kMaxLeafSize);
}

// A node or triangle read as 16-byte words: on the device four (node) or three (triangle) read-only 16-byte loads
// (`__ldg` of float4, LDG.E.128.CONSTANT in SASS) in place of one 4-byte load per field; on the host a plain copy.
// The same bytes either way, so every test on them computes the same result. Records are 16-byte aligned
// (alignas above; cudaMalloc gives 256-byte alignment).
RAYCOH_HD RAYCOH_INLINE BvhNode load_node_wide(const BvhNode* nodes, uint32_t i) {
#if defined(__CUDA_ARCH__)
  const float4* p = reinterpret_cast<const float4*>(nodes + i);
  const float4 a = __ldg(p), b = __ldg(p + 1), c = __ldg(p + 2), d = __ldg(p + 3);
  BvhNode n;
  n.lo0 = Vec3{a.x, a.y, a.z};
  n.hi0 = Vec3{a.w, b.x, b.y};
  n.lo1 = Vec3{b.z, b.w, c.x};
  n.hi1 = Vec3{c.y, c.z, c.w};
  n.child[0] = __float_as_int(d.x);
  n.child[1] = __float_as_int(d.y);
  n.pad[0] = n.pad[1] = 0;
  return n;
#else
  return nodes[i];
#endif
}
RAYCOH_HD RAYCOH_INLINE BvhTriangle load_triangle_wide(const BvhTriangle* tris, uint32_t i) {
#if defined(__CUDA_ARCH__)
  const float4* p = reinterpret_cast<const float4*>(tris + i);
  const float4 a = __ldg(p), b = __ldg(p + 1), c = __ldg(p + 2);
  BvhTriangle t;
  t.v0 = Vec3{a.x, a.y, a.z};
  t.prim = __float_as_uint(a.w);
  t.v1 = Vec3{b.x, b.y, b.z};
  t.v2 = Vec3{c.x, c.y, c.z};
  t.pad0 = t.pad1 = 0;
  return t;
#else
  return tris[i];
#endif
}

// Non-owning view of a flat BVH, valid on whichever side the arrays live. The root is node 0 and is always an
// inner node (a one-leaf scene gets a root whose second child is an empty leaf).
struct BvhView {
  const BvhNode* nodes = nullptr;
  const BvhTriangle* tris = nullptr;
  uint32_t node_count = 0;
  uint32_t tri_count = 0;
};

}  // namespace raycoh
