// The `ours` / `contiguous` grouping on the GPU: one block per tile, one thread per pixel number (tiles of at most
// 1024 pixels), the phases of generators/grouping_block.h separated by barriers. Every step is a shared
// host/device function (generators/grouping.h), the same the CPU tile loop calls, so the batches are equal byte
// for byte (tests/gpu_generators_test.cpp on a GPU; tests/grouping_test.cpp runs the same phases on the host).
// Group sums walk the tile's pixels in row-major order, the CPU's order: a float sum is only bit-identical in
// the same order. Run by the device pipeline (cuda/device_pipeline.h) and the gpu tests.
#include "cuda/cuda_check.cuh"
#include "cuda/device_common.cuh"
#include "generators/grouping_block.h"

namespace raycoh::cuda {

namespace {

// Phases 2, 4 and 6 (thread q < groups): the group's census, positions and donor, shared direction.
__device__ void census_phase(const TileBlock& b, unsigned long long* stats) {
  const uint32_t q = threadIdx.x;
  if (q < b.groups) {
    const GroupCensus census = phase_census(b, q);
    if (census.count > 0) atomicAdd(stats + kStatGroups + static_cast<int>(census.type()), 1ull);
  }
  __syncthreads();
  if (threadIdx.x == 0) phase_starts(b);
  __syncthreads();
  if (q < b.groups && b.sh.count[q] > 0) phase_positions(b, q);
  __syncthreads();
}

__device__ void shared_direction_phase(const TileBlock& b, unsigned long long* stats) {
  const uint32_t q = threadIdx.x;
  if (q < b.groups && b.sh.count[q] > 0 && b.sh.diffuse[q] > 0) {
    const SharedDirection d = phase_shared_direction(b, q);
    if (d.hybrid_fallback) atomicAdd(stats + kStatHybridFallback, 1ull);
    atomicAdd(stats + kStatReused, static_cast<unsigned long long>(reused_members(
                                       b.config, static_cast<GroupType>(b.sh.type[q]), d, b.sh.diffuse[q])));
  }
  __syncthreads();
}

// Tiles of up to 1024 pixels are one block each: the bound caps registers at 64 per thread, so that a 1024-thread
// block fits an SM's 65,536 registers (without it nvcc 13 gave this kernel 70 for sm_90, and a 32x32-tile launch
// failed with "too many resources requested for launch" on an H100).
__global__ void __launch_bounds__(kMaxGroupTile)
    group_kernel(GroupingConfig config, TileGrid grid, const ShadingPoint* points, const BsdfParams* materials,
                 const uint32_t* offsets, const uint32_t* scanline_slots, BatchView out, unsigned long long* stats) {
  extern __shared__ unsigned char shared_bytes[];
  __shared__ uint32_t warp_totals[32];
  const auto full_m = static_cast<uint32_t>(grid.tile_w * grid.tile_h);
  const TileGroups sh = carve_tile_groups(shared_bytes, full_m, (full_m + config.k - 1) / config.k);
  const TileBlock b = make_tile_block(config, grid, blockIdx.x, points, materials, sh);

  const uint32_t i = threadIdx.x;
  const bool hit = i < b.m && phase_assign(b, i);
  uint32_t hits;
  const uint32_t rank = block_exclusive_count(hit, warp_totals, hits);  // also publishes phase 1
  if (hits == 0) return;                                                // the same for the whole block
  census_phase(b, stats);

  const bool diffuse = hit && is_diffuse_like(sh.cls[i]);
  const size_t slot = hit ? pixel_slot(b, i, rank, offsets, scanline_slots) : 0;
  uint32_t flags = 0;
  if (hit && !diffuse) flags = phase_own_lobe(b, out, i, slot);
  __syncthreads();
  shared_direction_phase(b, stats);
  if (diffuse) flags = phase_reuse(b, out, i, slot);
  tally_block(hit, flags, stats);
}

}  // namespace

void launch_group_kernel(const GroupingConfig& config, const TileGrid& grid, const ShadingPoint* points,
                         const BsdfParams* materials, const uint32_t* offsets, const uint32_t* scanline_slots,
                         const BatchView& out, unsigned long long* stats) {
  const auto full_m = static_cast<uint32_t>(grid.tile_w * grid.tile_h);
  if (full_m > static_cast<uint32_t>(kMaxGroupTile) || config.k < 1)
    throw Error("cuda: GPU grouping needs tiles of at most 1024 pixels and k >= 1");
  const size_t shared = tile_groups_bytes(full_m, (full_m + config.k - 1) / config.k);
  if (shared > 48 * 1024)
    RAYCOH_CUDA_CHECK(
        cudaFuncSetAttribute(group_kernel, cudaFuncAttributeMaxDynamicSharedMemorySize, static_cast<int>(shared)));
  group_kernel<<<static_cast<unsigned>(grid.count()), round_up_warp(static_cast<int>(full_m)), shared>>>(
      config, grid, points, materials, offsets, scanline_slots, out, stats);
  RAYCOH_CUDA_CHECK_LAUNCH();
}

}  // namespace raycoh::cuda
