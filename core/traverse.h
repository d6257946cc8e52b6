// Closest-hit traversal of the flat BVH2, written once for host and device.
//
// While-while traversal after Aila & Laine (HPG 2009): an inner loop walks inner nodes and postpones the first
// leaf it meets; a second loop intersects the postponed leaves. The loop bodies are exposed as node_step() and
// leaf_step() so that a SIMT model can run lanes of a warp in lock step with exactly the control flow a GPU warp
// has; closest_hit() is the scalar driver. Triangles use the watertight test of Woop, Benthin and Wald
// ("Watertight Ray/Triangle Intersection", JCGT 2013), double-sided, with the double-precision fallback on
// exact-zero edge functions. Boxes use the slab test with Ize's conservative far-distance scaling
// ("Robust BVH Ray Traversal", JCGT 2013).
//
// Counting is a compile-time policy: Counters::on_node / on_leaf / on_triangle receive the index fetched.
// NoCounters compiles to nothing, so timing runs pay nothing for counting. So is the any-hit test of alpha MASK
// cut-outs (core/alpha_mask.h): Filter::accept(prim, b1, b2) decides whether a candidate hit closer than the
// current one counts; NoAlphaTest, the default, accepts all and compiles to nothing.
#pragma once

#include "core/alpha_mask.h"
#include "core/bvh.h"
#include "core/ray.h"

namespace raycoh {

struct NoCounters {
  RAYCOH_HD void on_node(int32_t) {}
  RAYCOH_HD void on_leaf(int32_t) {}
  RAYCOH_HD void on_triangle(uint32_t) {}
};

// Per-ray totals: inner nodes fetched, leaves visited, triangles tested.
struct RayCounters {
  uint32_t nodes = 0, leaves = 0, triangles = 0;
  RAYCOH_HD void on_node(int32_t) { ++nodes; }
  RAYCOH_HD void on_leaf(int32_t) { ++leaves; }
  RAYCOH_HD void on_triangle(uint32_t) { ++triangles; }
};

// Per-ray constants of the box and triangle tests.
struct PreparedRay {
  Vec3 org, dir, inv_dir;
  float tmin;
  int kx, ky, kz;    // watertight test: kz = dominant axis of dir
  float sx, sy, sz;  // shear constants
};

RAYCOH_HD RAYCOH_INLINE PreparedRay prepare_ray(const Ray& r) {
  PreparedRay p;
  p.org = r.org;
  p.dir = r.dir;
  p.tmin = r.tmin;
  // Avoid 0 * inf = NaN in the slab test: a zero component becomes a tiny one with its sign kept.
  const float eps = 1e-20f;
  p.inv_dir.x = 1.f / (fabsf(r.dir.x) > eps ? r.dir.x : copysignf(eps, r.dir.x));
  p.inv_dir.y = 1.f / (fabsf(r.dir.y) > eps ? r.dir.y : copysignf(eps, r.dir.y));
  p.inv_dir.z = 1.f / (fabsf(r.dir.z) > eps ? r.dir.z : copysignf(eps, r.dir.z));
  const float ax = fabsf(r.dir.x), ay = fabsf(r.dir.y), az = fabsf(r.dir.z);
  p.kz = (ax > ay) ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
  p.kx = p.kz == 2 ? 0 : p.kz + 1;
  p.ky = p.kx == 2 ? 0 : p.kx + 1;
  if (r.dir[p.kz] < 0.f) {  // keep the winding so that edge signs are consistent
    int t = p.kx;
    p.kx = p.ky;
    p.ky = t;
  }
  p.sz = 1.f / r.dir[p.kz];
  p.sx = r.dir[p.kx] * p.sz;
  p.sy = r.dir[p.ky] * p.sz;
  return p;
}

// min and max of the slab test. MinMaxInstructions (the tuned kernel's): on the device fminf / fmaxf, one FMNMX
// each, where the conditional form compiles to a compare and a select. They choose the same value: no operand is
// NaN (box planes are finite or infinite, the ray's origin finite and its inverse direction finite and non-zero,
// so a product is never 0 * inf), and where two operands compare equal they differ at most in the sign of a zero,
// which no use of the result can see (the results are only compared, or scaled and compared).
template <bool MinMaxInstructions>
RAYCOH_HD RAYCOH_INLINE float slab_min(float a, float b) {
#if defined(__CUDA_ARCH__)
  if constexpr (MinMaxInstructions) return fminf(a, b);
#endif
  return min_f(a, b);
}
template <bool MinMaxInstructions>
RAYCOH_HD RAYCOH_INLINE float slab_max(float a, float b) {
#if defined(__CUDA_ARCH__)
  if constexpr (MinMaxInstructions) return fmaxf(a, b);
#endif
  return max_f(a, b);
}

// Slab test; returns the entry distance, or +inf when [tmin, tmax] misses the box.
template <bool MinMaxInstructions = false>
RAYCOH_HD RAYCOH_INLINE float intersect_box(const PreparedRay& r, Vec3 lo, Vec3 hi, float tmax) {
  constexpr bool M = MinMaxInstructions;
  const float tx0 = (lo.x - r.org.x) * r.inv_dir.x, tx1 = (hi.x - r.org.x) * r.inv_dir.x;
  const float ty0 = (lo.y - r.org.y) * r.inv_dir.y, ty1 = (hi.y - r.org.y) * r.inv_dir.y;
  const float tz0 = (lo.z - r.org.z) * r.inv_dir.z, tz1 = (hi.z - r.org.z) * r.inv_dir.z;
  const float tnear = slab_max<M>(slab_max<M>(slab_min<M>(tx0, tx1), slab_min<M>(ty0, ty1)),
                                  slab_max<M>(slab_min<M>(tz0, tz1), r.tmin));
  // 1 + 2 gamma(3): makes the far distance conservative against rounding (Ize 2013).
  const float tfar =
      slab_min<M>(slab_min<M>(slab_max<M>(tx0, tx1), slab_max<M>(ty0, ty1)), slab_min<M>(slab_max<M>(tz0, tz1), tmax)) *
      1.00000024f;
  return tnear <= tfar ? tnear : __builtin_huge_valf();
}

// Watertight, double-sided ray/triangle test. Updates hit when the triangle is closer than hit.t and the filter
// accepts the hit.
template <class Filter = NoAlphaTest>
RAYCOH_HD RAYCOH_INLINE bool intersect_triangle(const PreparedRay& r, const BvhTriangle& tri, Hit& hit,
                                                const Filter& filter = Filter{}) {
  const Vec3 a = tri.v0 - r.org, b = tri.v1 - r.org, c = tri.v2 - r.org;
  const float ax = a[r.kx] - r.sx * a[r.kz], ay = a[r.ky] - r.sy * a[r.kz];
  const float bx = b[r.kx] - r.sx * b[r.kz], by = b[r.ky] - r.sy * b[r.kz];
  const float cx = c[r.kx] - r.sx * c[r.kz], cy = c[r.ky] - r.sy * c[r.kz];
  float u = cx * by - cy * bx;
  float v = ax * cy - ay * cx;
  float w = bx * ay - by * ax;
  if (u == 0.f || v == 0.f || w == 0.f) {  // exactly on an edge in float: decide in double
    u = static_cast<float>(static_cast<double>(cx) * by - static_cast<double>(cy) * bx);
    v = static_cast<float>(static_cast<double>(ax) * cy - static_cast<double>(ay) * cx);
    w = static_cast<float>(static_cast<double>(bx) * ay - static_cast<double>(by) * ax);
  }
  if ((u < 0.f || v < 0.f || w < 0.f) && (u > 0.f || v > 0.f || w > 0.f)) return false;
  const float det = u + v + w;
  if (det == 0.f) return false;
  // t from the plane equation rather than from the sheared vertex depths, whose weighted sum cancels badly when
  // the triangle is large compared with t (errors up to 1% of t on the shared scenes).
  const Vec3 ng = cross(tri.v1 - tri.v0, tri.v2 - tri.v0);
  const float t = dot(ng, a) / dot(ng, r.dir);
  if (!(t > r.tmin) || !(t < hit.t)) return false;
  const float inv_det = 1.f / det;
  const float b1 = v * inv_det, b2 = w * inv_det;
  if (!filter.accept(tri.prim, b1, b2)) return false;
  hit.t = t;
  hit.u = b1;  // weight of v1
  hit.v = b2;  // weight of v2
  hit.prim = tri.prim;
  return true;
}

// Where the traversal stack lives. InlineStackOf: inside the state, which the CPU tracers and the simt model keep per
// lane; on the GPU a dynamically indexed array makes nvcc place the *whole* state in local memory (the classic
// kernel's 352-byte frame: every read of the ray or the hit in a step is a local load). StackRefOf: the entries in an
// array of the caller's, so that the state's scalars stay in registers and only the stack is in local memory.
template <class Entry>
struct InlineStackOf {
  Entry entry[kTraversalStackSize];
  RAYCOH_HD Entry& operator[](int i) { return entry[i]; }
  RAYCOH_HD const Entry& operator[](int i) const { return entry[i]; }
};
template <class Entry>
struct StackRefOf {
  Entry* entry;
  RAYCOH_HD Entry& operator[](int i) const { return entry[i]; }
};

// Traversal state of one ray; the fields are what a GPU thread keeps in registers.
template <class Stack>
struct TraversalStateOf {
  PreparedRay ray;
  Hit hit;
  int32_t node_ref;  // next node to visit (inner or leaf), or kSentinel when done
  int32_t leaf_ref;  // postponed leaf (< 0), or >= 0 for none
  int sp;
  Stack stack;
};
using TraversalState = TraversalStateOf<InlineStackOf<int32_t>>;

// How a BVH2 kernel reads its records and where it keeps its stack: a compile-time policy of the traversal, like
// the counters. Both compute the same hits bit for bit (the same bytes, the same arithmetic); they differ in the
// instructions nvcc emits:
//   ClassicFetch  a node as 14 and a triangle as 10 scalar 4-byte loads (one per field read), the stack inside the
//                 state: the `cuda` tracer's BVH2 kernel until 2026-11 (`traversal=classic`), kept as the baseline.
//   WideFetch     a node as four and a triangle as three 16-byte read-only loads (load_node_wide,
//                 load_triangle_wide), the stack apart from the state, the slab test's min and max as single
//                 instructions (slab_min, slab_max) (`traversal=tuned`, the default).
// On the host both read the same struct; the CPU tracers and the simt model run ClassicFetch's code.
struct ClassicFetch {
  static constexpr bool kStackApart = false;
  static constexpr bool kMinMaxInstructions = false;
  RAYCOH_HD static const BvhNode& node(const BvhView& b, int32_t i) { return b.nodes[i]; }
  RAYCOH_HD static const BvhTriangle& triangle(const BvhView& b, uint32_t i) { return b.tris[i]; }
};
struct WideFetch {
  static constexpr bool kStackApart = true;
  static constexpr bool kMinMaxInstructions = true;
  RAYCOH_HD static BvhNode node(const BvhView& b, int32_t i) {
    return load_node_wide(b.nodes, static_cast<uint32_t>(i));
  }
  RAYCOH_HD static BvhTriangle triangle(const BvhView& b, uint32_t i) { return load_triangle_wide(b.tris, i); }
};

template <class State>
RAYCOH_HD RAYCOH_INLINE void traversal_begin(State& s, const Ray& r) {
  s.ray = prepare_ray(r);
  s.hit = Hit{};
  s.hit.t = r.tmax;
  s.stack[0] = kSentinel;
  s.sp = 1;
  s.node_ref = 0;
  s.leaf_ref = 0;
  // A ray with a non-finite or empty interval does no work at all.
  if (!(r.tmax > r.tmin) || !is_finite(r.org) || !is_finite(r.dir) || !(dot(r.dir, r.dir) > 0.f))
    s.node_ref = kSentinel;
}

template <class State>
RAYCOH_HD RAYCOH_INLINE bool traversal_wants_node(const State& s) {
  return s.node_ref >= 0 && s.node_ref != kSentinel;
}
template <class State>
RAYCOH_HD RAYCOH_INLINE bool traversal_has_leaf(const State& s) {
  return s.leaf_ref < 0;
}
template <class State>
RAYCOH_HD RAYCOH_INLINE bool traversal_done(const State& s) {
  return s.node_ref == kSentinel && s.leaf_ref >= 0;
}

// One iteration of the inner-node loop: fetch node_ref, enter the children the ray hits (nearer first),
// postpone the first leaf met.
template <class Counters, class Fetch = ClassicFetch, class State>
RAYCOH_HD RAYCOH_INLINE void node_step(State& s, const BvhView& bvh, Counters& counters) {
  const auto& n = Fetch::node(bvh, s.node_ref);
  counters.on_node(s.node_ref);
  const float t0 = intersect_box<Fetch::kMinMaxInstructions>(s.ray, n.lo0, n.hi0, s.hit.t);
  const float t1 = intersect_box<Fetch::kMinMaxInstructions>(s.ray, n.lo1, n.hi1, s.hit.t);
  const bool hit0 = t0 != __builtin_huge_valf();
  const bool hit1 = t1 != __builtin_huge_valf();
  if (!hit0 && !hit1) {
    s.node_ref = s.stack[--s.sp];
  } else {
    s.node_ref = hit0 ? n.child[0] : n.child[1];
    if (hit0 && hit1) {
      int32_t far_ref = n.child[1];
      if (t1 < t0) {
        far_ref = s.node_ref;
        s.node_ref = n.child[1];
      }
      s.stack[s.sp++] = far_ref;
    }
  }
  if (is_leaf_ref(s.node_ref) && s.leaf_ref >= 0) {
    s.leaf_ref = s.node_ref;
    s.node_ref = s.stack[--s.sp];
  }
}

// One iteration of the leaf loop: intersect the postponed leaf, then take node_ref as the next leaf if it is one.
template <class Counters, class Filter = NoAlphaTest, class Fetch = ClassicFetch, class State>
RAYCOH_HD RAYCOH_INLINE void leaf_step(State& s, const BvhView& bvh, Counters& counters,
                                       const Filter& filter = Filter{}) {
  counters.on_leaf(s.leaf_ref);
  const uint32_t first = leaf_first(s.leaf_ref), count = leaf_count(s.leaf_ref);
  for (uint32_t i = first; i < first + count; ++i) {
    counters.on_triangle(i);
    intersect_triangle(s.ray, Fetch::triangle(bvh, i), s.hit, filter);
  }
  s.leaf_ref = s.node_ref;
  if (is_leaf_ref(s.node_ref)) s.node_ref = s.stack[--s.sp];
}

// The while-while loop of one ray from traversal_begin to its end. A scalar "warp" of one lane leaves the node
// loop as soon as it holds a leaf, exactly as a GPU warp whose lanes all hold one.
template <class Fetch, class State, class Counters, class Filter>
RAYCOH_HD RAYCOH_INLINE void traverse(State& s, const BvhView& bvh, Counters& counters, const Filter& filter) {
  while (!traversal_done(s)) {
    while (traversal_wants_node(s)) {
      node_step<Counters, Fetch>(s, bvh, counters);
      if (traversal_has_leaf(s)) break;
    }
    while (traversal_has_leaf(s)) leaf_step<Counters, Filter, Fetch>(s, bvh, counters, filter);
  }
}

// Scalar driver: closest hit of one ray, read and stacked as Fetch says.
template <class Counters, class Filter = NoAlphaTest, class Fetch = ClassicFetch>
RAYCOH_HD RAYCOH_INLINE Hit closest_hit(const BvhView& bvh, const Ray& r, Counters& counters,
                                        const Filter& filter = Filter{}) {
  if constexpr (Fetch::kStackApart) {
    int32_t entries[kTraversalStackSize];
    TraversalStateOf<StackRefOf<int32_t>> s;
    s.stack.entry = entries;
    traversal_begin(s, r);
    traverse<Fetch>(s, bvh, counters, filter);
    return s.hit;
  } else {
    TraversalState s;
    traversal_begin(s, r);
    traverse<Fetch>(s, bvh, counters, filter);
    return s.hit;
  }
}

RAYCOH_HD RAYCOH_INLINE Hit closest_hit(const BvhView& bvh, const Ray& r) {
  NoCounters none;
  return closest_hit(bvh, r, none);
}

}  // namespace raycoh
