// Host API of the GPU traversal kernels (implemented in cuda/trace_kernels.cu; this header is plain C++ and is
// included by g++-compiled code such as the `cuda` tracer, cuda/cuda_tracer.cpp).
//
// Every kernel runs core/traverse.h unchanged over the flat BVH2 (64-byte nodes holding both children's boxes,
// Aila & Laine, "Understanding the Efficiency of Ray Traversal on GPUs", HPG 2009), so hits equal the `cpu`
// tracer's bit for bit. Kernels:
//   persistent  Aila & Laine's persistent threads: as many blocks as fit on the GPU at once; each warp takes the
//               next 32 consecutive rays of the batch from a global atomic counter, traces them (one ray per
//               lane, while-while loop), and fetches again until the batch is exhausted. A warp always holds 32
//               consecutive rays, the batch order's unit (DESIGN.md section 1), and load balancing is dynamic.
//   simple      one thread per ray, ceil(count / block) blocks: the baseline the persistent kernel must beat.
//   counting    one warp per 32 consecutive rays running the while-while loop warp-synchronously under the rules
//               of simt/simt.h, with __ballot_sync / __reduce_*_sync / __shfl_sync, and writing each warp's step
//               and per-ray counters. Not timed; it must reproduce the `simt` tracer's counters exactly.
// Indirect tracing: with an order array, lane i traces rays[order[i]] (the order is uploaded with the rays).
//
// CWBVH (Ylitie, Karras & Laine, HPG 2017; core/cwbvh.h): a DeviceTracer made from a CwbvhView runs the same
// persistent and simple kernels with core/traverse_cwbvh.h's closest_hit_cwbvh unchanged in place of closest_hit,
// so its hits equal the `cpu:bvh=cwbvh` tracer's bit for bit. It has no counting kernel (trace_counting throws).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/bvh.h"
#include "core/cwbvh.h"
#include "core/ray.h"
#include "core/warp_counters.h"

namespace raycoh::cuda {

enum class TraceKernel { Persistent, Simple };

struct TraceLaunch {
  TraceKernel kernel = TraceKernel::Persistent;
  int block = 128;  // threads per block: a multiple of 32 in [32, 1024]
};

// The BVH on the device (uploaded once by the constructor) and reusable ray/hit buffers (grown on demand).
// Throws raycoh::Error on any CUDA error, including "no device".
class DeviceTracer {
 public:
  explicit DeviceTracer(const BvhView& bvh);
  explicit DeviceTracer(const CwbvhView& bvh);  // the compressed 8-wide layout (no counting kernel)
  ~DeviceTracer();
  DeviceTracer(const DeviceTracer&) = delete;
  DeviceTracer& operator=(const DeviceTracer&) = delete;

  // Uploads rays (and order, when not null), traces lane i = rays[order ? order[i] : i] into hits[i], downloads
  // the hits. Only the kernel is timed (CUDA events): last_kernel_ms().
  void trace(const Ray* rays, const uint32_t* order, size_t count, Hit* hits, const TraceLaunch& launch);
  // The same on arrays that already live on the device (for a GPU-resident pipeline); returns the kernel ms.
  float trace_device(const Ray* d_rays, const uint32_t* d_order, size_t count, Hit* d_hits, const TraceLaunch& launch);

  // Counting run on host arrays: hits as trace(), plus warps[w] = the counters of lanes [32 w, 32 w + 32)
  // (warps is resized to ceil(count / 32)), counted in `layout`'s units (warp_size must be 32; take it from
  // simt_config(), which also checks that sector numbers fit 32 bits). block: threads per block, as above.
  void trace_counting(const Ray* rays, const uint32_t* order, size_t count, Hit* hits, const SimtConfig& layout,
                      int block, std::vector<WarpStepCounters>& warps);

  // Kernel time of the last trace / trace_counting call in milliseconds (CUDA events); -1 before the first.
  float last_kernel_ms() const;
  // Blocks the persistent kernel launches with this block size (SMs x resident blocks per SM).
  int persistent_blocks(int block) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace raycoh::cuda
