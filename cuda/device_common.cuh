// Block-level helpers of the generator kernels (cuda/device_primary.cu, device_generators.cu, device_per_pixel.cu,
// device_grouping.cu): statistics slots, block-wide counts, launch sizes. Included by .cu files only.
#pragma once

#include <cuda_runtime.h>

#include <string>

#include "core/batch_view.h"
#include "core/error.h"
#include "core/tile_grid.h"
#include "cuda/trace_kernels.h"
#include "generators/grouping.h"

namespace raycoh {
struct Camera;
}

namespace raycoh::cuda {

constexpr unsigned kFullMask = 0xffffffffu;
constexpr int kMaxGroupTile = 1024;  // ours / contiguous: one thread per pixel of a tile

// Statistics slots on the device (GenerationStats, in this order).
enum StatSlot : int {
  kStatRays = 0,
  kStatBelowGeometric = 1,
  kStatBelowShading = 2,
  kStatNonFinite = 3,
  kStatGroups = 4,  // 4 .. 8, indexed by GroupType
  kStatHybridFallback = 9,
  kStatReused = 10,
  kStatCount = 11,
};

// The block-wide combine of per-warp totals (each warp's lane wrote warp_totals[warp]): the sum over the warps
// before this one, and the block's total. Two barriers: warp_totals may be rewritten after it returns.
inline __device__ uint32_t warps_before(const uint32_t* warp_totals, uint32_t& total) {
  const unsigned warp = threadIdx.x >> 5;
  __syncthreads();
  uint32_t before = 0;
  total = 0;
  for (unsigned w = 0; w < (blockDim.x >> 5); ++w) {
    const uint32_t v = warp_totals[w];
    if (w < warp) before += v;
    total += v;
  }
  __syncthreads();
  return before;
}

// Exclusive count of `flag` over the block's threads in thread order, and the block's total. Every thread of the
// block calls it (blockDim.x a multiple of 32); warp_totals is __shared__ uint32_t[32].
inline __device__ uint32_t block_exclusive_count(bool flag, uint32_t* warp_totals, uint32_t& total) {
  const unsigned lane = threadIdx.x & 31u;
  const unsigned bits = __ballot_sync(kFullMask, flag);
  if (lane == 0) warp_totals[threadIdx.x >> 5] = static_cast<uint32_t>(__popc(bits));
  return warps_before(warp_totals, total) + static_cast<uint32_t>(__popc(bits & ((1u << lane) - 1u)));
}

// Exclusive sum of `value` over the block's threads in thread order, and the block's total (warp shuffles, one
// barrier pair). Every thread of the block calls it (blockDim.x a multiple of 32); warp_totals is
// __shared__ uint32_t[32].
inline __device__ uint32_t block_exclusive_sum(uint32_t value, uint32_t* warp_totals, uint32_t& total) {
  const unsigned lane = threadIdx.x & 31u;
  uint32_t inclusive = value;
  for (unsigned d = 1; d < 32; d <<= 1) {
    const uint32_t v = __shfl_up_sync(kFullMask, inclusive, d);
    if (lane >= d) inclusive += v;
  }
  if (lane == 31) warp_totals[threadIdx.x >> 5] = inclusive;
  return warps_before(warp_totals, total) + inclusive - value;
}

// Statistics of one block in shared memory (shared atomics), added to the global ones once per block.
struct BlockStats {
  uint32_t* slots;  // __shared__ uint32_t[kStatCount]
  __device__ void clear() const {
    if (threadIdx.x < kStatCount) slots[threadIdx.x] = 0;
  }
  __device__ void add(int slot, uint32_t n) const {
    if (n) atomicAdd(slots + slot, n);
  }
  // After a barrier: one global atomic per non-zero slot.
  __device__ void flush(unsigned long long* stats) const {
    if (threadIdx.x < kStatCount && slots[threadIdx.x])
      atomicAdd(stats + threadIdx.x, static_cast<unsigned long long>(slots[threadIdx.x]));
  }
};

// Adds each thread's tallies of emitted rays into the block's statistics.
inline __device__ void tally_block(bool emitted, uint32_t flags, const BlockStats& stats) {
  const int rays = __syncthreads_count(emitted);
  const int below_geometric = __syncthreads_count(emitted && (flags & kSampleBelowGeometric));
  const int below_shading = __syncthreads_count(emitted && (flags & kSampleBelowShading));
  const int non_finite = __syncthreads_count(emitted && (flags & kSampleNonFinite));
  if (threadIdx.x == 0) {
    stats.add(kStatRays, static_cast<uint32_t>(rays));
    stats.add(kStatBelowGeometric, static_cast<uint32_t>(below_geometric));
    stats.add(kStatBelowShading, static_cast<uint32_t>(below_shading));
    stats.add(kStatNonFinite, static_cast<uint32_t>(non_finite));
  }
}

inline unsigned blocks_for(size_t n, int block) {
  const size_t blocks = (n + static_cast<size_t>(block) - 1) / static_cast<size_t>(block);
  if (blocks > 0x7fffffffu) throw Error("cuda: " + std::to_string(n) + " threads are too many for one launch");
  return static_cast<unsigned>(blocks);
}

inline int round_up_warp(int n) { return (n + 31) / 32 * 32; }

// The grouping kernel (cuda/device_grouping.cu): one block per tile of `grid`, rays into `out`, statistics into
// `stats` (kStatCount slots). offsets: first slot of each tile; scanline_slots: per pixel, for scanline order.
void launch_group_kernel(const GroupingConfig& config, const TileGrid& grid, const ShadingPoint* points,
                         const BsdfParams* materials, const uint32_t* offsets, const uint32_t* scanline_slots,
                         const BatchView& out, unsigned long long* stats);

// The batch a fused trace also writes (cuda/fused_kernels.cu): none (offsets null), or `out` with each tile's rays
// from offsets[tile] in the materialized generator's slots.
struct FusedBatch {
  BatchView out{};
  const uint32_t* offsets = nullptr;
};

// The fused trace of ours / contiguous (cuda/fused_kernels.cu; noopt, sadeghi and microjitter:
// launch_fused_per_pixel, cuda/pixel_numbers.cuh): one block per tile makes the tile's rays with `config` and
// traces them with the launch's kernel form over `scene`; hits[pixel] for every ray's pixel, or with a batch
// hits[slot] for every ray's batch slot.
void launch_fused_grouping(const DeviceScene& scene, const TraceLaunch& launch, const GroupingConfig& config,
                           const TileGrid& grid, const ShadingPoint* points, const BsdfParams* materials,
                           const FusedBatch& batch, Hit* hits, unsigned long long* stats);

// Camera rays of make_primary_rays_gpu (cuda/device_primary.cu) into device arrays of width x height entries,
// queued on the default stream (nothing waited for): d_rays[slot] and d_pixels[slot] in the batch order.
void launch_primary_rays(const Camera& camera, int width, int height, RayOrder order, int tile_w, int tile_h,
                         uint32_t seed, uint32_t frame, bool jitter, Ray* d_rays, uint32_t* d_pixels);

}  // namespace raycoh::cuda
