// The fused trace of `cuda:pipeline=fused`: no ray batch in memory. Persistent warps (as many as the GPU holds at
// once) each take the next tile from a global counter, make the tile's secondary rays from the G-buffer exactly as
// the materialized generators do (the same shared host/device functions: sample_own_lobe for noopt, the phases of
// generators/grouping_block.h for ours / contiguous, so the rays are the CPU generator's bit for bit), keep them
// in the warp's shared memory in the batch's order within the tile (tile order, or group order for order=group),
// and trace them 32 at a time: a warp holds the rays a warp of the materialized batch holds wherever the tile's
// hits fill whole warps. For ours, the group's shared direction is computed once per group in shared memory, as
// the paper does. A warp needs no other warp: it synchronises with __syncwarp only, so a warp whose rays finish
// early takes the next tile at once (a block per tile would hold its warps until the slowest ray ended). Each hit
// is written at its ray's pixel (hits[pixel]); the generation statistics gather in shared memory and reach the
// global counters once per block.
#include <cuda_runtime.h>

#include <algorithm>

#include "core/own_lobe.h"
#include "core/secondary_ray.h"
#include "cuda/cuda_check.cuh"
#include "cuda/device_common.cuh"
#include "cuda/ray_io.cuh"
#include "cuda/trace_ray.cuh"
#include "generators/grouping_block.h"

namespace raycoh::cuda {

namespace {

constexpr int kFusedBlock = 128;  // at most 4 persistent warps a block (fewer where a tile's state is large)

// A warp's rays of the current tile: ray, pixel and (grouping) each hit pixel's rank in the tile, per slot.
struct Staged {
  Ray* rays;
  uint32_t* pixel;
  uint32_t* rank;  // [pixel number] rank among the tile's hits in row-major order (grouping only)
};
__host__ __device__ inline size_t align16(size_t bytes) { return (bytes + 15) / 16 * 16; }
// Bytes of one warp's shared memory: `state` bytes of tile state, then `slots` staged rays.
__host__ __device__ inline size_t warp_bytes(size_t state, uint32_t slots) {
  return align16(align16(state) + size_t{slots} * (sizeof(Ray) + 2 * sizeof(uint32_t)));
}
__device__ inline Staged carve_staged(unsigned char* warp_base, size_t state, uint32_t slots) {
  Ray* rays = reinterpret_cast<Ray*>(warp_base + align16(state));
  uint32_t* pixel = reinterpret_cast<uint32_t*>(rays + slots);
  return Staged{rays, pixel, pixel + slots};
}

// The next tile of the warp (lane 0 asks the counter; every lane gets it).
__device__ inline uint32_t next_tile(uint32_t* counter) {
  uint32_t t = 0;
  if ((threadIdx.x & 31u) == 0) t = atomicAdd(counter, 1u);
  return __shfl_sync(kFullMask, t, 0);
}

// The ray tallies of one round of the warp (every lane calls it): lane 0 adds them to the block's statistics.
__device__ inline void tally_warp(bool emitted, uint32_t flags, const BlockStats& stats) {
  const int rays = __popc(__ballot_sync(kFullMask, emitted));
  const int below_geometric = __popc(__ballot_sync(kFullMask, emitted && (flags & kSampleBelowGeometric)));
  const int below_shading = __popc(__ballot_sync(kFullMask, emitted && (flags & kSampleBelowShading)));
  const int non_finite = __popc(__ballot_sync(kFullMask, emitted && (flags & kSampleNonFinite)));
  if ((threadIdx.x & 31u) == 0) {
    stats.add(kStatRays, static_cast<uint32_t>(rays));
    stats.add(kStatBelowGeometric, static_cast<uint32_t>(below_geometric));
    stats.add(kStatBelowShading, static_cast<uint32_t>(below_shading));
    stats.add(kStatNonFinite, static_cast<uint32_t>(non_finite));
  }
}

// Traces staged slots [0, count) 32 at a time, each hit at its ray's pixel.
template <class View, class Filter>
__device__ void trace_staged(const View& view, const Filter& filter, const Staged& staged, uint32_t count, Hit* hits) {
  for (uint32_t s = threadIdx.x & 31u; s < count; s += 32)
    store_hit(hits, staged.pixel[s], trace_ray(view, staged.rays[s], filter));
}

// noopt: 32 pixel numbers of the tile at a time, the hit ones compacted into the warp's 32 slots and traced.
template <class View, class Filter>
__global__ void __launch_bounds__(kFusedBlock, 8)
    fused_noopt_kernel(View view, Filter filter, const ShadingPoint* points, const BsdfParams* materials, uint32_t seed,
                       uint32_t frame, TileGrid grid, size_t warp_size, Hit* hits, unsigned long long* stats,
                       uint32_t* counter) {
  extern __shared__ unsigned char shared_bytes[];
  __shared__ uint32_t block_slots[kStatCount];
  const BlockStats block_stats{block_slots};
  block_stats.clear();
  __syncthreads();
  const uint32_t lane = threadIdx.x & 31u;
  const Staged staged = carve_staged(shared_bytes + (threadIdx.x >> 5) * warp_size, 0, 32);
  const auto tiles = static_cast<uint32_t>(grid.count());
  for (uint32_t t = next_tile(counter); t < tiles; t = next_tile(counter)) {
    const TileRect rect = grid.rect(static_cast<int>(t));
    for (uint32_t base = 0; base < rect.area(); base += 32) {
      const uint32_t i = base + lane, p = i < rect.area() ? rect.pixel(i, grid.width) : 0u;
      const bool hit = i < rect.area() && has_hit(points[p]);
      const unsigned ballot = __ballot_sync(kFullMask, hit);
      uint32_t flags = 0;
      if (hit) {
        const uint32_t slot = __popc(ballot & ((1u << lane) - 1u));
        const ShadingPoint& sp = points[p];
        const SecondaryRay r =
            make_secondary_ray(sp.position, sp.ng, sp.ns, sample_own_lobe(materials[sp.material], sp, seed, frame, p));
        staged.rays[slot] = r.ray;
        staged.pixel[slot] = p;
        flags = r.flags;
      }
      tally_warp(hit, flags, block_stats);
      __syncwarp();
      trace_staged(view, filter, staged, static_cast<uint32_t>(__popc(ballot)), hits);
      __syncwarp();  // the slots are rewritten by the next round
    }
  }
  __syncthreads();
  block_stats.flush(stats);
}

// ---- ours / contiguous: the phases of generators/grouping_block.h for one tile in one warp ----------------------

// Ray of hit pixel i from its direction, staged at its slot in the batch's order within the tile.
__device__ inline uint32_t stage_pixel(const TileBlock& b, const Staged& staged, uint32_t i, const DirectionSample& s) {
  const uint32_t slot = b.config.order == RayOrder::Group ? b.sh.pos[i] : staged.rank[i];
  const uint32_t p = b.rect.pixel(i, b.image_width);
  const ShadingPoint& sp = b.points[p];
  const SecondaryRay r = make_secondary_ray(sp.position, sp.ng, sp.ns, s);
  staged.rays[slot] = r.ray;
  staged.pixel[slot] = p;
  return r.flags;
}

// Phases 1 to 4: groups, ranks, census, first positions (a warp scan), positions and donors. Returns the hits.
__device__ uint32_t warp_census(const TileBlock& b, const Staged& staged, const BlockStats& stats) {
  const uint32_t lane = threadIdx.x & 31u;
  uint32_t hits = 0;
  for (uint32_t base = 0; base < b.m; base += 32) {
    const uint32_t i = base + lane;
    const bool hit = i < b.m && phase_assign(b, i);
    const unsigned ballot = __ballot_sync(kFullMask, hit);
    if (hit) staged.rank[i] = hits + __popc(ballot & ((1u << lane) - 1u));
    hits += __popc(ballot);
  }
  __syncwarp();
  if (hits == 0) return 0;
  for (uint32_t i = lane; i < b.m; i += 32)
    if (b.sh.flags[i] & kPixelHit) phase_member_rank(b, i);
  for (uint32_t q = lane; q < b.groups; q += 32) {
    const GroupCensus census = phase_census(b, q);
    if (census.count > 0) stats.add(kStatGroups + static_cast<int>(census.type()), 1);
  }
  __syncwarp();
  uint32_t carry = 0;  // first positions: an exclusive scan of the counts, 32 groups at a time
  for (uint32_t base = 0; base < b.groups; base += 32) {
    const uint32_t q = base + lane, count = q < b.groups ? b.sh.count[q] : 0u;
    uint32_t inclusive = count;
    for (uint32_t d = 1; d < 32; d <<= 1) {
      const uint32_t v = __shfl_up_sync(kFullMask, inclusive, d);
      if (lane >= d) inclusive += v;
    }
    if (q < b.groups) b.sh.start[q] = carry + inclusive - count;
    carry += __shfl_sync(kFullMask, inclusive, 31);
  }
  __syncwarp();
  for (uint32_t q = lane; q < b.groups; q += 32)
    if (b.sh.count[q] > 0) phase_positions(b, q);
  __syncwarp();
  return hits;
}

// Phases 5 to 7: own lobes (staged, mean votes), shared directions, the diffuse-like members' reuse (staged).
__device__ void warp_directions(const TileBlock& b, const Staged& staged, const BlockStats& stats) {
  const uint32_t lane = threadIdx.x & 31u;
  for (uint32_t base = 0; base < b.m; base += 32) {
    const uint32_t i = base + lane;
    const bool own = i < b.m && (b.sh.flags[i] & kPixelHit) && !is_diffuse_like(b.sh.cls[i]);
    const uint32_t flags = own ? stage_pixel(b, staged, i, own_lobe_sample(b, i)) : 0u;
    tally_warp(own, flags, stats);
  }
  __syncwarp();
  for (uint32_t q = lane; q < b.groups; q += 32) {
    if (b.sh.count[q] == 0 || b.sh.diffuse[q] == 0) continue;
    const SharedDirection d = phase_shared_direction(b, q);
    stats.add(kStatHybridFallback, d.hybrid_fallback ? 1u : 0u);
    stats.add(kStatReused, reused_members(b.config, static_cast<GroupType>(b.sh.type[q]), d, b.sh.diffuse[q]));
  }
  __syncwarp();
  for (uint32_t base = 0; base < b.m; base += 32) {
    const uint32_t i = base + lane;
    const bool reuse = i < b.m && (b.sh.flags[i] & kPixelHit) && is_diffuse_like(b.sh.cls[i]);
    const uint32_t flags = reuse ? stage_pixel(b, staged, i, reuse_sample(b, i)) : 0u;
    tally_warp(reuse, flags, stats);
  }
  __syncwarp();
}

template <class View, class Filter>
__global__ void __launch_bounds__(kFusedBlock, 8)
    fused_group_kernel(View view, Filter filter, GroupingConfig config, TileGrid grid, const ShadingPoint* points,
                       const BsdfParams* materials, size_t state, size_t warp_size, Hit* hits,
                       unsigned long long* stats, uint32_t* counter) {
  extern __shared__ unsigned char shared_bytes[];
  __shared__ uint32_t block_slots[kStatCount];
  const BlockStats block_stats{block_slots};
  block_stats.clear();
  __syncthreads();
  const auto full_m = static_cast<uint32_t>(grid.tile_w * grid.tile_h);
  unsigned char* mine = shared_bytes + (threadIdx.x >> 5) * warp_size;
  const TileGroups sh = carve_tile_groups(mine, full_m, (full_m + config.k - 1) / config.k, config.k);
  const Staged staged = carve_staged(mine, state, full_m);
  const auto tiles = static_cast<uint32_t>(grid.count());
  for (uint32_t t = next_tile(counter); t < tiles; t = next_tile(counter)) {
    const TileBlock b = make_tile_block(config, grid, t, points, materials, sh);
    const uint32_t count = warp_census(b, staged, block_stats);
    if (count == 0) continue;
    warp_directions(b, staged, block_stats);
    trace_staged(view, filter, staged, count, hits);
    __syncwarp();  // the tile state is rewritten by the next tile
  }
  __syncthreads();
  block_stats.flush(stats);
}

// Warps a block of the fused kernel (at most 4): as many as the device's shared memory a block allows.
int warps_per_block(size_t per_warp) {
  int device = 0;
  RAYCOH_CUDA_CHECK(cudaGetDevice(&device));
  cudaDeviceProp prop{};
  RAYCOH_CUDA_CHECK(cudaGetDeviceProperties(&prop, device));
  // The opt-in limit (GPGPU-Sim leaves it 0: then the default 48 KB).
  const size_t limit = prop.sharedMemPerBlockOptin > 0 ? prop.sharedMemPerBlockOptin : prop.sharedMemPerBlock;
  const size_t fit = per_warp > 0 ? limit / per_warp : 4;
  if (fit < 1)
    throw Error("cuda: the fused trace needs " + std::to_string(per_warp) + " bytes of shared memory a warp for this " +
                "tile, over the " + std::to_string(limit) + " a block may have; use a smaller tile or " +
                "cuda:pipeline=device");
  return static_cast<int>(std::min<size_t>(4, fit));
}

// Resident blocks of the kernel (`warps` warps and `shared` bytes a block), but no more warps than tiles.
template <class Kernel>
unsigned persistent_grid(Kernel kernel, int warps, size_t shared, size_t tiles) {
  if (shared > 48 * 1024)
    RAYCOH_CUDA_CHECK(
        cudaFuncSetAttribute(kernel, cudaFuncAttributeMaxDynamicSharedMemorySize, static_cast<int>(shared)));
  int per_sm = 0, device = 0, sms = 0;
  RAYCOH_CUDA_CHECK(cudaOccupancyMaxActiveBlocksPerMultiprocessor(&per_sm, kernel, warps * 32, shared));
  RAYCOH_CUDA_CHECK(cudaGetDevice(&device));
  RAYCOH_CUDA_CHECK(cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, device));
  const size_t wanted = (tiles + size_t(warps) - 1) / size_t(warps);
  return static_cast<unsigned>(
      std::max<size_t>(1, std::min<size_t>(wanted, size_t(std::max(1, per_sm)) * size_t(sms))));
}

}  // namespace

void launch_fused_noopt(const DeviceScene& scene, const TraceLaunch& launch, const ShadingPoint* points,
                        const BsdfParams* materials, uint32_t seed, uint32_t frame, const TileGrid& grid, Hit* hits,
                        unsigned long long* stats, uint32_t* counter) {
  const size_t per_warp = warp_bytes(0, 32);
  const int warps = warps_per_block(per_warp);
  const size_t shared = per_warp * size_t(warps);
  RAYCOH_CUDA_CHECK(cudaMemsetAsync(counter, 0, sizeof(uint32_t)));
  with_trace_view(scene, launch, [&](auto view, auto filter) {
    auto kernel = fused_noopt_kernel<decltype(view), decltype(filter)>;
    const unsigned blocks = persistent_grid(kernel, warps, shared, static_cast<size_t>(grid.count()));
    kernel<<<blocks, warps * 32, shared>>>(view, filter, points, materials, seed, frame, grid, per_warp, hits, stats,
                                           counter);
  });
  RAYCOH_CUDA_CHECK_LAUNCH();
}

void launch_fused_grouping(const DeviceScene& scene, const TraceLaunch& launch, const GroupingConfig& config,
                           const TileGrid& grid, const ShadingPoint* points, const BsdfParams* materials, Hit* hits,
                           unsigned long long* stats, uint32_t* counter) {
  const auto full_m = static_cast<uint32_t>(grid.tile_w * grid.tile_h);
  if (full_m > static_cast<uint32_t>(kMaxGroupTile) || config.k < 1)
    throw Error("cuda: the fused trace groups tiles of at most 1024 pixels with k >= 1");
  if (config.order == RayOrder::Scanline)
    throw Error("cuda: the fused trace makes each tile's rays in one warp; order=scanline has no fused form");
  const size_t state = tile_groups_bytes(full_m, (full_m + config.k - 1) / config.k, config.k);
  const size_t per_warp = warp_bytes(state, full_m);
  const int warps = warps_per_block(per_warp);
  const size_t shared = per_warp * size_t(warps);
  RAYCOH_CUDA_CHECK(cudaMemsetAsync(counter, 0, sizeof(uint32_t)));
  with_trace_view(scene, launch, [&](auto view, auto filter) {
    auto kernel = fused_group_kernel<decltype(view), decltype(filter)>;
    const unsigned blocks = persistent_grid(kernel, warps, shared, static_cast<size_t>(grid.count()));
    kernel<<<blocks, warps * 32, shared>>>(view, filter, config, grid, points, materials, state, per_warp, hits, stats,
                                           counter);
  });
  RAYCOH_CUDA_CHECK_LAUNCH();
}

}  // namespace raycoh::cuda
