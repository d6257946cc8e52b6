// Host API of the GPU traversal kernels (implemented in cuda/trace_kernels.cu; this header is plain C++ and is
// included by g++-compiled code such as the `cuda` tracer, cuda/cuda_tracer.cpp).
//
// Every kernel runs core/traverse.h unchanged over the flat BVH2 (64-byte nodes holding both children's boxes,
// Aila & Laine, "Understanding the Efficiency of Ray Traversal on GPUs", HPG 2009), so hits equal the `cpu`
// tracer's bit for bit, in either traversal form (TraceLaunch::traversal: tuned or classic loads). Kernels:
//   persistent  Aila & Laine's persistent threads: as many blocks as fit on the GPU at once; each warp takes the
//               next 32 consecutive rays of the batch from a global atomic counter, traces them (one ray per
//               lane, while-while loop), and fetches again until the batch is exhausted. A warp always holds 32
//               consecutive rays, the batch order's unit (docs/design.md section 1), and load balancing is dynamic.
//   simple      one thread per ray, ceil(count / block) blocks: the baseline the persistent kernel must beat.
//   counting    one warp per 32 consecutive rays running the while-while loop warp-synchronously under the rules
//               of simt/simt.h, with __ballot_sync / __reduce_*_sync / __shfl_sync, and writing each warp's step
//               and per-ray counters. Not timed; it must reproduce the `simt` tracer's counters exactly.
// Indirect tracing: with an order array, lane i traces rays[order[i]] (the order is uploaded with the rays).
//
// CWBVH (Ylitie, Karras & Laine, HPG 2017; core/cwbvh.h): a DeviceTracer made from a CwbvhView runs the same
// persistent and simple kernels with core/traverse_cwbvh.h's closest_hit_cwbvh unchanged in place of closest_hit,
// so its hits equal the `cpu:bvh=cwbvh` tracer's bit for bit. It has no counting kernel (trace_counting throws).
//
// Alpha MASK cut-outs (core/alpha_mask.h): a DeviceTracer made with a scene's AlphaMaskArrays uploads them once
// with the BVH and runs every kernel (persistent, simple, counting; BVH2 and CWBVH) with the AlphaTest filter, the
// same any-hit test the CPU tracers run, so its hits equal theirs bit for bit on masked scenes too. Without masks
// (empty arrays) the kernels are the NoAlphaTest instances, the code that ran before masks existed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/alpha_mask.h"
#include "core/bvh.h"
#include "core/cwbvh.h"
#include "core/ray.h"
#include "core/warp_counters.h"

namespace raycoh::cuda {

enum class TraceKernel { Persistent, Simple };
// How the BVH2 kernels read the BVH and keep their state (core/traverse.h, ClassicFetch and WideFetch): tuned, the
// default, 16-byte read-only loads and the state in registers; classic, the kernel as it was until 2026-11 (a
// 4-byte load per field, the whole traversal state in local memory), kept as the baseline. The CWBVH kernels have
// one form (16-byte loads, the stack apart from the state).
enum class Bvh2Traversal { Tuned, Classic };

struct TraceLaunch {
  TraceKernel kernel = TraceKernel::Persistent;
  int block = 128;  // threads per block: a multiple of 32 in [32, 1024]
  Bvh2Traversal traversal = Bvh2Traversal::Tuned;
  // CWBVH only: the traversal stack in shared memory ((depth + 2) 8-byte entries per thread) instead of local memory.
  bool shared_stack = false;
};

// A scene's alpha MASK arrays on the host (scenes/scene.h AlphaMasks); tri_count == 0: no masks.
struct AlphaMaskArrays {
  const uint32_t* tri_texture = nullptr;  // tri_count entries: texture index, or kNoAlphaMask
  const float* tri_uv = nullptr;          // 6 * tri_count
  size_t tri_count = 0;
  const AlphaTexture* textures = nullptr;
  size_t texture_count = 0;
  const uint8_t* texels = nullptr;
  size_t texel_count = 0;
  bool empty() const { return tri_count == 0; }
};

// Why the device could not test these arrays without reading out of bounds (empty when it can): every BVH
// triangle's prim has an entry, every entry names a texture or none, every texture is non-empty and lies inside
// the texels. Plain host code (the DeviceTracer checks before it uploads; tests run it without a GPU).
inline std::string alpha_arrays_error(const AlphaMaskArrays& a, const BvhTriangle* tris, uint32_t tri_count) {
  for (uint32_t i = 0; i < tri_count; ++i)
    if (tris[i].prim >= a.tri_count)
      return "triangle " + std::to_string(tris[i].prim) + " has no alpha entry (" + std::to_string(a.tri_count) +
             " entries)";
  for (size_t i = 0; i < a.tri_count; ++i)
    if (a.tri_texture[i] != kNoAlphaMask && a.tri_texture[i] >= a.texture_count)
      return "triangle " + std::to_string(i) + " names alpha texture " + std::to_string(a.tri_texture[i]) + " of " +
             std::to_string(a.texture_count);
  for (size_t i = 0; i < a.texture_count; ++i) {
    const AlphaTexture& t = a.textures[i];
    const uint64_t size = uint64_t{t.width} * t.height;
    if (size == 0 || t.width > 0x7fffffffu || t.height > 0x7fffffffu || t.offset > a.texel_count ||
        size > a.texel_count - t.offset)
      return "alpha texture " + std::to_string(i) + " (" + std::to_string(t.width) + " x " + std::to_string(t.height) +
             " at " + std::to_string(t.offset) + ") is not inside the " + std::to_string(a.texel_count) + " texels";
  }
  return "";
}

// Why a launch's kernel choices cannot run on a tracer of this layout (empty when they can): classic is a BVH2
// kernel, a shared stack a CWBVH kernel's. Plain host code: the `cuda` tracer checks its parameters with it before
// it needs a device, DeviceTracer::check_launch before every launch.
inline std::string launch_choice_error(const TraceLaunch& launch, bool cwbvh) {
  if (cwbvh && launch.traversal == Bvh2Traversal::Classic)
    return "traversal=classic is a BVH2 kernel; bvh=cwbvh has one kernel (traversal=tuned)";
  if (!cwbvh && launch.shared_stack)
    return "stack=shared is the CWBVH kernel's (bvh=cwbvh); the BVH2 kernels keep their stack in local memory";
  return "";
}

// A tracer's arrays on the device, for a kernel that traces inside itself (cuda/fused_kernels.cu, through
// with_trace_view of cuda/trace_ray.cuh): one of the two layouts (the other's nodes are null) and the alpha MASK
// arrays where the scene has masks.
struct DeviceScene {
  BvhView bvh{};
  CwbvhView cwbvh{};
  bool cwbvh_layout = false;
  bool masked = false;
  AlphaMaskView alpha{};
};

// The BVH on the device (uploaded once by the constructor) and reusable ray/hit buffers (grown on demand).
// Throws raycoh::Error on any CUDA error, including "no device".
class DeviceTracer {
 public:
  // alpha: the scene's MASK arrays (uploaded too; every kernel then runs the AlphaTest filter), or empty. Throws
  // raycoh::Error when alpha_arrays_error() finds them inconsistent with the BVH.
  explicit DeviceTracer(const BvhView& bvh, const AlphaMaskArrays& alpha = {});
  // The compressed 8-wide layout (no counting kernel); depth: the tree's depth (Cwbvh stats.max_depth), which bounds
  // the traversal stack of a ray and sizes the shared-memory stack of stack=shared.
  explicit DeviceTracer(const CwbvhView& bvh, const AlphaMaskArrays& alpha = {},
                        uint32_t depth = kTraversalStackSize - 2);
  ~DeviceTracer();
  DeviceTracer(const DeviceTracer&) = delete;
  DeviceTracer& operator=(const DeviceTracer&) = delete;

  // Uploads rays (and order, when not null), traces lane i = rays[order ? order[i] : i] into hits[i], downloads
  // the hits. Only the kernel is timed (CUDA events): last_kernel_ms().
  void trace(const Ray* rays, const uint32_t* order, size_t count, Hit* hits, const TraceLaunch& launch);
  // The same on arrays that already live on the device (for a GPU-resident pipeline); returns the kernel ms.
  float trace_device(const Ray* d_rays, const uint32_t* d_order, size_t count, Hit* d_hits, const TraceLaunch& launch);
  // trace_device in two steps: launch (queued on the default stream between the timer's events, nothing waited
  // for), then wait_kernel_ms() (waits, sets last_kernel_ms() and returns it).
  void launch_device(const Ray* d_rays, const uint32_t* d_order, size_t count, Hit* d_hits, const TraceLaunch& launch);
  float wait_kernel_ms();

  // Counting run on host arrays: hits as trace(), plus warps[w] = the counters of lanes [32 w, 32 w + 32)
  // (warps is resized to ceil(count / 32)), counted in `layout`'s units (warp_size must be 32; take it from
  // simt_config(), which also checks that sector numbers fit 32 bits). block: threads per block, as above.
  void trace_counting(const Ray* rays, const uint32_t* order, size_t count, Hit* hits, const SimtConfig& layout,
                      int block, std::vector<WarpStepCounters>& warps);
  // The same on device arrays (d_hits stays on the device; warps are downloaded).
  void trace_counting_device(const Ray* d_rays, const uint32_t* d_order, size_t count, Hit* d_hits,
                             const SimtConfig& layout, int block, std::vector<WarpStepCounters>& warps);

  // Kernel time of the last trace / trace_counting call in milliseconds (CUDA events); -1 before the first.
  float last_kernel_ms() const;
  // Blocks the persistent kernel launches with this launch (SMs x resident blocks per SM).
  int persistent_blocks(const TraceLaunch& launch) const;
  // Throws raycoh::Error when the launch cannot run on this tracer (block size, a shared stack that does not fit).
  void check_launch(const TraceLaunch& launch) const;
  // Whether the kernels run the alpha MASK test (the tracer was made with non-empty AlphaMaskArrays).
  bool alpha_masked() const;
  // The uploaded arrays (valid while the tracer lives).
  DeviceScene device_scene() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace raycoh::cuda
