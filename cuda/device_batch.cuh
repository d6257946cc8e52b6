// A ray batch on the device: a buffer per column of RAYCOH_BATCH_COLUMNS (core/ray_batch.h), its view, its download
// and the gather of every column through an order. Expanded from the one column list, as the host batch is, so a
// new ray attribute needs no change here. Used by the device generators (cuda/device_generators.cu) and the
// device pipeline's permuted batch (cuda/device_stages.cu). Included by .cu files only.
#pragma once

#include <cuda_runtime.h>

#include "core/batch_view.h"
#include "core/ray_batch.h"
#include "cuda/cuda_check.cuh"

namespace raycoh::cuda {

struct DeviceBatch {
#define RAYCOH_DEVICE_COLUMN(name, T, is_group) DeviceBuffer<T> name;
  RAYCOH_BATCH_COLUMNS(RAYCOH_DEVICE_COLUMN)
#undef RAYCOH_DEVICE_COLUMN

  // Room for n rays (the group columns only when grouped); the columns' view, the group ones null otherwise.
  BatchView reserve(size_t n, bool grouped) {
    BatchView v;
#define RAYCOH_RESERVE(name, T, is_group) \
  if (!is_group || grouped) {             \
    name.reserve(n);                      \
    v.name = name.get();                  \
  }
    RAYCOH_BATCH_COLUMNS(RAYCOH_RESERVE)
#undef RAYCOH_RESERVE
    return v;
  }

  // The first n rays into `out` (resized; the group columns when grouped).
  void download(RayBatch& out, size_t n, bool grouped) const {
    out.resize(n, grouped);
#define RAYCOH_DOWNLOAD(name, T, is_group) \
  if (!is_group || grouped) name.download(out.name.data(), n);
    RAYCOH_BATCH_COLUMNS(RAYCOH_DOWNLOAD)
#undef RAYCOH_DOWNLOAD
  }
};

template <class T>
__device__ __forceinline__ void gather_element(T* out, const T* in, size_t i, uint32_t j) {
  out[i] = in[j];
}
// Rays as two 16-byte words (device buffers are 256-byte aligned, rays 32 bytes).
__device__ __forceinline__ void gather_element(Ray* out, const Ray* in, size_t i, uint32_t j) {
  const float4* src = reinterpret_cast<const float4*>(in + j);
  float4* dst = reinterpret_cast<float4*>(out + i);
  dst[0] = __ldg(src);
  dst[1] = __ldg(src + 1);
}

// Element i of every column `out` has is element order[i] of `in`'s.
__device__ __forceinline__ void gather_columns(const BatchView& in, uint32_t j, size_t i, const BatchView& out) {
#define RAYCOH_GATHER_COLUMN(name, T, is_group) \
  if (out.name) gather_element(out.name, in.name, i, j);
  RAYCOH_BATCH_COLUMNS(RAYCOH_GATHER_COLUMN)
#undef RAYCOH_GATHER_COLUMN
}

}  // namespace raycoh::cuda
