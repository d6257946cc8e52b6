// Device discovery and a one-call closest-hit helper (implemented in cuda/cuda_device.cu; callable from g++ code).
// The kernels, the persistent-thread tracer and the counting kernel are in cuda/trace_kernels.h; the `cuda`
// tracer (cuda/cuda_tracer.cpp) is what the harness uses. Hits equal the `cpu` tracer's exactly.
#pragma once

#include <cstddef>
#include <string>

#include "core/bvh.h"
#include "core/ray.h"

namespace raycoh::cuda {

// Number of usable CUDA devices; 0 when there is no GPU or no driver (any CUDA error counts as "no GPU").
int device_count();
// Name and compute capability of device 0, or "" without a GPU.
std::string device_name();

// Threads device 0 keeps resident at most: SMs x the SM's resident thread limit (maxThreadsPerMultiProcessor), the
// size of one wave of a batch at full occupancy; 0 without a GPU.
long long device_resident_threads();

// Uploads the BVH and rays, traces every ray with one thread each (the `simple` kernel), downloads the hits.
// kernel_ms receives the kernel time measured with CUDA events (transfers excluded). Throws raycoh::Error on any
// CUDA error.
void trace_closest(const BvhView& bvh, const Ray* rays, size_t count, Hit* hits, float* kernel_ms);

}  // namespace raycoh::cuda
