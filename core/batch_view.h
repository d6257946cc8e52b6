// A ray batch's arrays as plain pointers, and the one function that writes a ray into it: used by the CPU
// generators (over a RayBatch's vectors) and by the CUDA kernels (over device buffers).
#pragma once

#include "core/bsdf.h"
#include "core/platform.h"
#include "core/ray_batch.h"
#include "core/secondary_ray.h"

namespace raycoh {

// A pointer per column of RAYCOH_BATCH_COLUMNS (core/ray_batch.h); the group columns are null for generators
// without groups.
struct BatchView {
#define RAYCOH_BATCH_POINTER(name, T, grouped) T* name = nullptr;
  RAYCOH_BATCH_COLUMNS(RAYCOH_BATCH_POINTER)
#undef RAYCOH_BATCH_POINTER
};

// The batch's storage (it must already have its size: RayBatch::resize).
inline BatchView batch_view(RayBatch& b) {
  BatchView v;
#define RAYCOH_BATCH_DATA(name, T, grouped) v.name = b.name.data();
  RAYCOH_BATCH_COLUMNS(RAYCOH_BATCH_DATA)
#undef RAYCOH_BATCH_DATA
  return v;
}

// Ray `slot` from a shading point and the direction chosen for it. The origin is offset along the geometric
// normal on the side the direction leaves; a non-finite position yields a finite stand-in ray with weight 0,
// flagged kSampleNonFinite in the returned flags.
RAYCOH_HD RAYCOH_INLINE uint32_t write_ray(const BatchView& out, size_t slot, const ShadingPoint& sp, uint32_t pixel,
                                           const DirectionSample& s) {
  const SecondaryRay r = make_secondary_ray(sp.position, sp.ng, sp.ns, s);
#ifdef __CUDA_ARCH__
  // Two 16-byte stores (device buffers are 256-byte aligned, rays 32 bytes): a warp's stores to consecutive
  // slots are then 2 contiguous spans instead of 8 strided ones.
  float4* ray_words = reinterpret_cast<float4*>(out.rays + slot);
  ray_words[0] = make_float4(r.ray.org.x, r.ray.org.y, r.ray.org.z, r.ray.tmin);
  ray_words[1] = make_float4(r.ray.dir.x, r.ray.dir.y, r.ray.dir.z, r.ray.tmax);
#else
  out.rays[slot] = r.ray;
#endif
  out.weight[slot] = r.weight;
  out.normal[slot] = r.normal;
  out.pixel[slot] = pixel;
  out.pdf[slot] = s.pdf;
  out.material[slot] = sp.cls;
  return r.flags;
}

// The group columns of ray `slot` (grouping generators).
RAYCOH_HD RAYCOH_INLINE void write_group(const BatchView& out, size_t slot, uint32_t tile, uint32_t group,
                                         GroupType type) {
  out.tile[slot] = tile;
  out.group[slot] = group;
  out.group_type[slot] = type;
}

}  // namespace raycoh
