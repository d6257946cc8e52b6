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

// What identifies device 0 in a measured row (cuda/gpu_facts.cu): its SM count, the driver's version (the NVIDIA
// driver's from NVML, with the CUDA version the driver supports) and the CUDA runtime's; empty without a GPU.
struct DeviceFacts {
  int sms = 0;
  std::string driver, runtime;
};
DeviceFacts device_facts();

// Device 0's current SM and memory clocks in MHz (NVML); 0 where NVML cannot say (no driver library, GPGPU-Sim).
struct DeviceClocks {
  int sm_mhz = 0, mem_mhz = 0;
};
DeviceClocks device_clocks();

// Uploads the BVH and rays, traces every ray with one thread each (the `simple` kernel), downloads the hits.
// kernel_ms receives the kernel time measured with CUDA events (transfers excluded). Throws raycoh::Error on any
// CUDA error.
void trace_closest(const BvhView& bvh, const Ray* rays, size_t count, Hit* hits, float* kernel_ms);

}  // namespace raycoh::cuda
