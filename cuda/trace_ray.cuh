// The closest hit of one ray in each layout and form the trace kernels run (cuda/trace_kernels.cu), for every kernel
// that traces: the persistent and simple kernels, and the fused trace that makes its rays itself
// (cuda/fused_kernels.cu). Each is the shared traversal of core/traverse.h or core/traverse_cwbvh.h, unchanged, so
// every kernel's hits equal the `cpu` tracer's. Included by .cu files only.
#pragma once

#include <cuda_runtime.h>

#include "core/alpha_mask.h"
#include "core/traverse.h"
#include "core/traverse_cwbvh.h"
#include "cuda/trace_kernels.h"

namespace raycoh::cuda {
// The closest hit of one ray in either layout under the filter: the shared traversals, unchanged (with
// NoAlphaTest these are closest_hit(bvh, r) and closest_hit_cwbvh(bvh, r), the same instantiations).
template <class Filter>
__device__ __forceinline__ Hit trace_ray(const BvhView& bvh, const Ray& r, const Filter& filter) {
  NoCounters none;
  return closest_hit(bvh, r, none, filter);
}
// The tuned BVH2 kernel's view: the same arrays, read with 16-byte loads and the stack apart (WideFetch).
struct WideBvhView {
  BvhView bvh;
};
template <class Filter>
__device__ __forceinline__ Hit trace_ray(const WideBvhView& v, const Ray& r, const Filter& filter) {
  NoCounters none;
  return closest_hit<NoCounters, Filter, WideFetch>(v.bvh, r, none, filter);
}
// The CWBVH kernel with its stack in shared memory (`stack=shared`): entry i of a thread at
// stack_memory[i * blockDim.x + threadIdx.x], 8 bytes each (a warp's accesses to one level fall in distinct
// banks); the launch gives each block (the tree's depth + 2) * blockDim.x entries of dynamic shared memory.
struct SharedStackCwbvhView {
  CwbvhView bvh;
};
struct StridedStackRef {
  uint64_t* base;
  uint32_t stride;
  __device__ uint64_t& operator[](int i) const { return base[static_cast<uint32_t>(i) * stride]; }
};
template <class Filter>
__device__ __forceinline__ Hit trace_ray(const SharedStackCwbvhView& v, const Ray& r, const Filter& filter) {
  extern __shared__ uint64_t stack_memory[];
  NoCounters none;
  CwbvhStateOf<StridedStackRef> s;
  s.stack = StridedStackRef{stack_memory + threadIdx.x, blockDim.x};
  cwbvh_begin(s, r);
  cwbvh_traverse(s, v.bvh, none, filter);
  return s.hit;
}
template <class Filter>
__device__ __forceinline__ Hit trace_ray(const CwbvhView& bvh, const Ray& r, const Filter& filter) {
  NoCounters none;
  return closest_hit_cwbvh(bvh, r, none, filter);
}

// Calls f(view, filter) with the view and filter types the launch traces this scene with (the tuned or classic
// BVH2, or the CWBVH with its stack in local memory; the alpha MASK filter where the scene has masks). The CWBVH
// shared-memory stack is the persistent kernel's alone (it owns the block's dynamic shared memory).
template <class F>
void with_trace_view(const DeviceScene& scene, const TraceLaunch& launch, F&& f) {
  const AlphaTest alpha{scene.alpha};
  if (scene.cwbvh_layout) {
    if (scene.masked)
      f(scene.cwbvh, alpha);
    else
      f(scene.cwbvh, NoAlphaTest{});
  } else if (launch.traversal == Bvh2Traversal::Tuned) {
    if (scene.masked)
      f(WideBvhView{scene.bvh}, alpha);
    else
      f(WideBvhView{scene.bvh}, NoAlphaTest{});
  } else if (scene.masked) {
    f(scene.bvh, alpha);
  } else {
    f(scene.bvh, NoAlphaTest{});
  }
}

}  // namespace raycoh::cuda
