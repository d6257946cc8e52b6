// The `ours` / `contiguous` phases of one tile as one block-wide device function, shared by the materialized group
// kernel (cuda/device_grouping.cu: writes each ray into the batch) and the fused trace (cuda/fused_kernels.cu:
// traces each ray where it is made). One block per tile, thread i = pixel number i (blockDim.x >= the full tile's
// pixels); the phases are generators/grouping_block.h's, separated by barriers. Included by .cu files only.
#pragma once

#include "cuda/device_common.cuh"
#include "generators/grouping_block.h"

namespace raycoh::cuda {

// This block's tile and its state in dynamic shared memory (tile_groups_bytes(full tile, groups, k) bytes).
inline __device__ TileBlock tile_block(const GroupingConfig& config, const TileGrid& grid, const ShadingPoint* points,
                                       const BsdfParams* materials, unsigned char* shared_bytes) {
  const auto full_m = static_cast<uint32_t>(grid.tile_w * grid.tile_h);
  const TileGroups sh = carve_tile_groups(shared_bytes, full_m, (full_m + config.k - 1) / config.k, config.k);
  return make_tile_block(config, grid, blockIdx.x, points, materials, sh);
}

// What the phases leave to thread i: whether pixel i has a ray, its rank among the tile's hits in row-major
// order, the tile's hit count, and its direction (own lobe or the group's).
struct TilePhases {
  bool hit = false;
  uint32_t rank = 0, hits = 0;
  DirectionSample sample{};
};

// Every phase of the tile; group statistics (groups by type, hybrid fallbacks, reused rays) into `stats`.
// Returns with hits == 0 for the whole block when the tile has no hit (the later phases are skipped).
inline __device__ TilePhases group_phases(const TileBlock& b, uint32_t* warp_totals, const BlockStats& stats) {
  const uint32_t i = threadIdx.x, q = threadIdx.x;
  stats.clear();
  TilePhases t;
  t.hit = i < b.m && phase_assign(b, i);
  t.rank = block_exclusive_count(t.hit, warp_totals, t.hits);  // also publishes phase 1
  if (t.hits == 0) return t;
  // Phase 2: each member's rank in its group, each group's census.
  if (t.hit) phase_member_rank(b, i);
  uint32_t count = 0;
  if (q < b.groups) {
    const GroupCensus census = phase_census(b, q);
    count = census.count;
    if (count > 0) stats.add(kStatGroups + static_cast<int>(census.type()), 1);
  }
  // Phase 3: first positions (a block scan; it also publishes phase 2), phase 4: positions and donors.
  uint32_t total;
  const uint32_t start = block_exclusive_sum(count, warp_totals, total);
  if (q < b.groups) b.sh.start[q] = start;
  __syncthreads();
  if (q < b.groups && count > 0) phase_positions(b, q);
  __syncthreads();
  // Phase 5: own lobes (and mean votes); 6: shared directions; 7: the diffuse-like members' reuse.
  const bool diffuse = t.hit && is_diffuse_like(b.sh.cls[i]);
  if (t.hit && !diffuse) t.sample = own_lobe_sample(b, i);
  __syncthreads();
  if (q < b.groups && count > 0 && b.sh.diffuse[q] > 0) {
    const SharedDirection d = phase_shared_direction(b, q);
    stats.add(kStatHybridFallback, d.hybrid_fallback ? 1u : 0u);
    stats.add(kStatReused, reused_members(b.config, static_cast<GroupType>(b.sh.type[q]), d, b.sh.diffuse[q]));
  }
  __syncthreads();
  if (diffuse) t.sample = reuse_sample(b, i);
  return t;
}

}  // namespace raycoh::cuda
