// The `ours` / `contiguous` grouping on the GPU: one block per tile, one thread per pixel number (tiles of at most
// 1024 pixels), the phases of generators/grouping_block.h separated by barriers. Every step is a shared
// host/device function (generators/grouping.h), the same the CPU tile loop calls, so the batches are equal byte
// for byte (tests/gpu_generators_test.cpp on a GPU; tests/grouping_test.cpp runs the same phases on the host).
// No thread walks the tile: a group's phases visit only its k slots or its members (in row-major order, the CPU's,
// so the float sums are the CPU's), the groups' first positions are a block scan, and the statistics gather in
// shared memory and reach the global counters once per block. Run by the device pipeline
// (cuda/device_pipeline.h), its fused trace (cuda/fused_kernels.cu) and the gpu tests.
#include "cuda/cuda_check.cuh"
#include "cuda/device_common.cuh"
#include "cuda/device_grouping.cuh"

namespace raycoh::cuda {

namespace {

// Tiles of up to 1024 pixels are one block each: the bound caps registers at 64 per thread, so that a 1024-thread
// block fits an SM's 65,536 registers (without it nvcc 13 gave this kernel 70 for sm_90, and a 32x32-tile launch
// failed with "too many resources requested for launch" on an H100).
__global__ void __launch_bounds__(kMaxGroupTile)
    group_kernel(GroupingConfig config, TileGrid grid, const ShadingPoint* points, const BsdfParams* materials,
                 const uint32_t* offsets, const uint32_t* scanline_slots, BatchView out, unsigned long long* stats) {
  extern __shared__ unsigned char shared_bytes[];
  __shared__ uint32_t warp_totals[32];
  __shared__ uint32_t block_slots[kStatCount];
  const BlockStats block_stats{block_slots};
  const TileBlock b = tile_block(config, grid, points, materials, shared_bytes);
  const TilePhases t = group_phases(b, warp_totals, block_stats);
  if (t.hits == 0) return;  // the same for the whole block
  const uint32_t i = threadIdx.x;
  uint32_t flags = 0;
  if (t.hit) flags = write_pixel(b, out, i, pixel_slot(b, i, t.rank, offsets, scanline_slots), t.sample);
  tally_block(t.hit, flags, block_stats);
  __syncthreads();
  block_stats.flush(stats);
}

}  // namespace

void launch_group_kernel(const GroupingConfig& config, const TileGrid& grid, const ShadingPoint* points,
                         const BsdfParams* materials, const uint32_t* offsets, const uint32_t* scanline_slots,
                         const BatchView& out, unsigned long long* stats) {
  const auto full_m = static_cast<uint32_t>(grid.tile_w * grid.tile_h);
  if (full_m > static_cast<uint32_t>(kMaxGroupTile) || config.k < 1)
    throw Error("cuda: GPU grouping needs tiles of at most 1024 pixels and k >= 1");
  const size_t shared = tile_groups_bytes(full_m, (full_m + config.k - 1) / config.k, config.k);
  if (shared > 48 * 1024)
    RAYCOH_CUDA_CHECK(
        cudaFuncSetAttribute(group_kernel, cudaFuncAttributeMaxDynamicSharedMemorySize, static_cast<int>(shared)));
  group_kernel<<<static_cast<unsigned>(grid.count()), round_up_warp(static_cast<int>(full_m)), shared>>>(
      config, grid, points, materials, offsets, scanline_slots, out, stats);
  RAYCOH_CUDA_CHECK_LAUNCH();
}

}  // namespace raycoh::cuda
