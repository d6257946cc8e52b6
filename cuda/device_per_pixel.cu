// noopt, sadeghi and microjitter on the GPU (cuda/device_generators.h explains the method): one block per tile, its
// hit pixels ranked row-major with warp ballots, each writing its ray at the tile's offset. The per-ray math is the
// shared host/device code the CPU generators call (core/own_lobe.h, core/batch_view.h, core/shading_point.h,
// generators/shared_sample.h), pinned by the gpu-labelled tests (tests/gpu_generators_test.cpp,
// tests/gpu_shared_sample_test.cpp).
#include <cuda_runtime.h>

#include <algorithm>

#include "core/shading_point.h"
#include "cuda/cuda_check.cuh"
#include "cuda/pixel_numbers.cuh"

namespace raycoh::cuda {

namespace {

// The body of a per-pixel kernel, one block per tile: its hit pixels ranked row-major (warp ballots), each writes
// its ray at the tile's offset.
template <class Numbers>
__device__ __forceinline__ void per_pixel_rays(const ShadingPoint* points, const BsdfParams* materials, uint32_t seed,
                                               uint32_t frame, const TileGrid& grid, const uint32_t* offsets,
                                               const BatchView& out, unsigned long long* stats,
                                               const Numbers& numbers) {
  __shared__ uint32_t warp_totals[32];
  const int t = blockIdx.x;
  int x0, y0, w, h;
  grid.rect(t, x0, y0, w, h);
  const int m = w * h;
  uint32_t next = offsets[t];
  // Tallies of this thread's rays (a thread may write several in a large tile).
  uint32_t rays = 0, below_geometric = 0, below_shading = 0, non_finite = 0;
  for (int base = 0; base < m; base += blockDim.x) {
    const int i = base + static_cast<int>(threadIdx.x);
    const auto x = static_cast<uint32_t>(i < m ? x0 + i % w : 0), y = static_cast<uint32_t>(i < m ? y0 + i / w : 0);
    const auto p = static_cast<uint32_t>(i < m ? y * grid.width + x : 0);
    const ShadingPoint sp = load_point(points, p);  // four 16-byte loads (core/shading_point.h)
    const bool hit = i < m && has_hit(sp);
    uint32_t total;
    const uint32_t rank = block_exclusive_count(hit, warp_totals, total);
    if (hit) {
      const DirectionSample s = numbers(materials[sp.material], sp, seed, frame, x, y, p);
      const uint32_t flags = write_ray(out, next + rank, sp, p, s);
      ++rays;
      below_geometric += (flags & kSampleBelowGeometric) != 0;
      below_shading += (flags & kSampleBelowShading) != 0;
      non_finite += (flags & kSampleNonFinite) != 0;
    }
    next += total;
  }
  // Few rays per block: shared-memory sums, then one global atomic per counter.
  __shared__ unsigned long long sums[4];
  if (threadIdx.x < 4) sums[threadIdx.x] = 0;
  __syncthreads();
  if (rays) atomicAdd(&sums[0], static_cast<unsigned long long>(rays));
  if (below_geometric) atomicAdd(&sums[1], static_cast<unsigned long long>(below_geometric));
  if (below_shading) atomicAdd(&sums[2], static_cast<unsigned long long>(below_shading));
  if (non_finite) atomicAdd(&sums[3], static_cast<unsigned long long>(non_finite));
  __syncthreads();
  if (threadIdx.x < 4 && sums[threadIdx.x]) atomicAdd(stats + kStatRays + threadIdx.x, sums[threadIdx.x]);
  // sadeghi, microjitter: every ray's numbers came from a shared stream unless each pixel has its own.
  if constexpr (Numbers::kCountsReuse)
    if (threadIdx.x == 0 && numbers.reused && sums[0]) atomicAdd(stats + kStatReused, sums[0]);
}

// Two kernels, so that each keeps its own name (scripts/count-stage-instructions reads noopt_kernel's SASS).
__global__ void noopt_kernel(const ShadingPoint* points, const BsdfParams* materials, uint32_t seed, uint32_t frame,
                             TileGrid grid, const uint32_t* offsets, BatchView out, unsigned long long* stats) {
  per_pixel_rays(points, materials, seed, frame, grid, offsets, out, stats, OwnNumbers{});
}
__global__ void shared_sample_kernel(const ShadingPoint* points, const BsdfParams* materials, uint32_t seed,
                                     uint32_t frame, TileGrid grid, const uint32_t* offsets, BatchView out,
                                     unsigned long long* stats, SharedNumbers numbers) {
  per_pixel_rays(points, materials, seed, frame, grid, offsets, out, stats, numbers);
}

}  // namespace

void launch_per_pixel_kernel(const TileGrid& grid, const ShadingPoint* points, const BsdfParams* materials,
                             uint32_t seed, uint32_t frame, const uint32_t* offsets, const BatchView& out,
                             unsigned long long* stats, const SharedNumbers* shared) {
  const int block = std::min(256, round_up_warp(grid.tile_w * grid.tile_h));
  const auto blocks = static_cast<unsigned>(grid.count());
  if (shared)
    shared_sample_kernel<<<blocks, block>>>(points, materials, seed, frame, grid, offsets, out, stats, *shared);
  else
    noopt_kernel<<<blocks, block>>>(points, materials, seed, frame, grid, offsets, out, stats);
  RAYCOH_CUDA_CHECK_LAUNCH();
}

}  // namespace raycoh::cuda
