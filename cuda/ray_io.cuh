// Loading a ray and storing a hit in the trace kernels (cuda/trace_kernels.cu, cuda/counting_kernel.cu). Included by
// .cu files only.
#pragma once

#include <cuda_runtime.h>

#include "core/ray.h"

namespace raycoh::cuda {

// Rays are 32 bytes and buffers come from cudaMalloc (256-byte aligned): two 16-byte read-only loads.
__device__ __forceinline__ Ray load_ray(const Ray* rays, size_t i) {
  const float4* p = reinterpret_cast<const float4*>(rays + i);
  const float4 a = __ldg(p), b = __ldg(p + 1);
  Ray r;
  r.org = Vec3{a.x, a.y, a.z};
  r.tmin = a.w;
  r.dir = Vec3{b.x, b.y, b.z};
  r.tmax = b.w;
  return r;
}

// Hits are 16 bytes: one store.
__device__ __forceinline__ void store_hit(Hit* hits, size_t i, const Hit& h) {
  reinterpret_cast<float4*>(hits)[i] = make_float4(h.t, __uint_as_float(h.prim), h.u, h.v);
}

}  // namespace raycoh::cuda
