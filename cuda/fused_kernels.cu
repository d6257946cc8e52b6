// The fused trace of `cuda:pipeline=fused`: no ray batch in memory. One block per tile makes the tile's secondary
// rays from the G-buffer, exactly as the materialized generators do (cuda/device_generators.cu for noopt,
// cuda/device_grouping.cuh for ours / contiguous: the same shared host/device functions, so the rays are the
// CPU generator's bit for bit), keeps them in shared memory in the batch's order within the tile, and traces them
// at once: thread t traces the tile's t-th ray of that order (tile order, or group order for order=group), so a
// warp holds the rays a warp of the materialized batch holds wherever the tile's hits fill whole warps. For ours,
// the group's shared direction is computed once per group in shared memory, as the paper does. Each hit is written
// at its ray's pixel (hits[pixel]); the generation statistics are gathered per block in shared memory.
// With a batch (FusedBatch: the device path tracer's fused first bounce, whose shading reads the rays' pixels,
// pdfs and weights after the trace), each block also writes its rays into the batch at its tile's offset, in the
// materialized generator's slots, and each hit at its ray's slot (hits[slot]); the trace still reads each ray from
// shared memory, where the block made it.
#include <cuda_runtime.h>

#include <type_traits>

#include "core/own_lobe.h"
#include "core/secondary_ray.h"
#include "cuda/cuda_check.cuh"
#include "cuda/device_common.cuh"
#include "cuda/device_grouping.cuh"
#include "cuda/pixel_numbers.cuh"
#include "cuda/ray_io.cuh"
#include "cuda/trace_ray.cuh"

namespace raycoh::cuda {

namespace {

// The staged rays of one block: ray and pixel of slot s (the tile's s-th ray), after `offset` bytes of other state.
struct Staged {
  Ray* rays;
  uint32_t* pixel;
};
__host__ __device__ inline size_t staged_offset(size_t state_bytes) { return (state_bytes + 15) / 16 * 16; }
__host__ __device__ inline size_t staged_bytes(size_t state_bytes, uint32_t slots) {
  return staged_offset(state_bytes) + static_cast<size_t>(slots) * (sizeof(Ray) + sizeof(uint32_t));
}
__device__ inline Staged carve_staged(unsigned char* base, size_t state_bytes, uint32_t slots) {
  Ray* rays = reinterpret_cast<Ray*>(base + staged_offset(state_bytes));
  return Staged{rays, reinterpret_cast<uint32_t*>(rays + slots)};
}

// `first` of trace_staged: each hit at its ray's pixel (no batch).
constexpr size_t kAtPixel = ~size_t{0};

// Thread t traces staged slot t (t < count) into hits[pixel], or with a batch into hits[first + t] (the staged
// slot's batch slot). Between two barriers of the caller.
template <class View, class Filter>
__device__ void trace_staged(const View& view, const Filter& filter, const Staged& staged, uint32_t count, Hit* hits,
                             size_t first) {
  if (threadIdx.x < count) {
    const size_t at = first == kAtPixel ? staged.pixel[threadIdx.x] : first + threadIdx.x;
    store_hit(hits, at, trace_ray(view, staged.rays[threadIdx.x], filter));
  }
}

// noopt, sadeghi, microjitter (Numbers: cuda/pixel_numbers.cuh, as the materialized kernel samples): a tile's hit
// pixels in row-major order, blockDim.x at a time (a tile may have more pixels than threads).
template <class View, class Filter, class Numbers>
__global__ void __launch_bounds__(256, 4)
    fused_per_pixel_kernel(View view, Filter filter, const ShadingPoint* points, const BsdfParams* materials,
                           uint32_t seed, uint32_t frame, TileGrid grid, FusedBatch batch, Hit* hits,
                           unsigned long long* stats, Numbers numbers) {
  extern __shared__ unsigned char shared_bytes[];
  __shared__ uint32_t warp_totals[32];
  __shared__ uint32_t block_slots[kStatCount];
  const BlockStats block_stats{block_slots};
  block_stats.clear();
  const Staged staged = carve_staged(shared_bytes, 0, blockDim.x);
  const TileRect rect = grid.rect(static_cast<int>(blockIdx.x));
  const auto m = static_cast<int>(rect.area());
  size_t next = batch.offsets ? batch.offsets[blockIdx.x] : kAtPixel;  // the round's first batch slot
  for (int base = 0; base < m; base += blockDim.x) {
    const int i = base + static_cast<int>(threadIdx.x);
    const uint32_t p = i < m ? rect.pixel(static_cast<uint32_t>(i), grid.width) : 0u;
    const ShadingPoint sp = load_point(points, p);  // four 16-byte loads (core/shading_point.h)
    const bool hit = i < m && has_hit(sp);
    uint32_t total;
    const uint32_t rank = block_exclusive_count(hit, warp_totals, total);
    uint32_t flags = 0;
    if (hit) {
      const auto x = static_cast<uint32_t>(rect.x0 + i % rect.w), y = static_cast<uint32_t>(rect.y0 + i / rect.w);
      const DirectionSample s = numbers(materials[sp.material], sp, seed, frame, x, y, p);
      const SecondaryRay r = make_secondary_ray(sp.position, sp.ng, sp.ns, s);
      staged.rays[rank] = r.ray;
      staged.pixel[rank] = p;
      flags = r.flags;
      if (batch.offsets) write_ray(batch.out, next + rank, sp, p, s);
    }
    tally_block(hit, flags, block_stats);  // its barriers also publish the staged rays
    trace_staged(view, filter, staged, total, hits, next);
    if (batch.offsets) next += total;
    __syncthreads();  // the staged slots are rewritten by the next round
  }
  // sadeghi, microjitter: every ray's numbers came from a shared stream unless each pixel has its own.
  if constexpr (Numbers::kCountsReuse)
    if (threadIdx.x == 0 && numbers.reused) block_slots[kStatReused] += block_slots[kStatRays];
  __syncthreads();
  block_stats.flush(stats);
}

// ours / contiguous: the tile's phases (cuda/device_grouping.cuh), then its rays in the batch's order in the tile.
template <class View, class Filter>
__global__ void __launch_bounds__(kMaxGroupTile)
    fused_group_kernel(View view, Filter filter, GroupingConfig config, TileGrid grid, const ShadingPoint* points,
                       const BsdfParams* materials, size_t state_bytes, FusedBatch batch, Hit* hits,
                       unsigned long long* stats) {
  extern __shared__ unsigned char shared_bytes[];
  __shared__ uint32_t warp_totals[32];
  __shared__ uint32_t block_slots[kStatCount];
  const BlockStats block_stats{block_slots};
  const TileBlock b = tile_block(config, grid, points, materials, shared_bytes);
  const TilePhases t = group_phases(b, warp_totals, block_stats);
  if (t.hits == 0) return;  // the same for the whole block
  const Staged staged = carve_staged(shared_bytes, state_bytes, blockDim.x);
  const uint32_t i = threadIdx.x;
  uint32_t flags = 0;
  if (t.hit) {
    // The tile's first position is 0 (start[0] = 0), so pos is the slot in group order.
    const uint32_t slot = config.order == RayOrder::Group ? b.sh.pos[i] : t.rank;
    const uint32_t p = b.rect.pixel(i, b.image_width);
    const ShadingPoint sp = load_point(points, p);
    const SecondaryRay r = make_secondary_ray(sp.position, sp.ng, sp.ns, t.sample);
    staged.rays[slot] = r.ray;
    staged.pixel[slot] = p;
    flags = r.flags;
    if (batch.offsets) write_pixel(b, batch.out, i, batch.offsets[b.tile] + slot, t.sample);  // pixel_slot's
  }
  tally_block(t.hit, flags, block_stats);  // its barriers also publish the staged rays
  trace_staged(view, filter, staged, t.hits, hits, batch.offsets ? batch.offsets[b.tile] : kAtPixel);
  __syncthreads();
  block_stats.flush(stats);
}

// Lets the kernel have `shared` bytes of dynamic shared memory; one line when the device cannot give a block that.
template <class Kernel>
void allow_shared(Kernel kernel, size_t shared) {
  int device = 0;
  RAYCOH_CUDA_CHECK(cudaGetDevice(&device));
  cudaDeviceProp prop{};
  RAYCOH_CUDA_CHECK(cudaGetDeviceProperties(&prop, device));
  // The opt-in limit (GPGPU-Sim leaves it 0: then the default 48 KB).
  const size_t limit = prop.sharedMemPerBlockOptin > 0 ? prop.sharedMemPerBlockOptin : prop.sharedMemPerBlock;
  if (shared > limit)
    throw Error("cuda: the fused trace needs " + std::to_string(shared) +
                " bytes of shared memory for one tile, over " + "the " + std::to_string(limit) +
                " a block may have; use a smaller tile or cuda:pipeline=device");
  if (shared > 48 * 1024)
    RAYCOH_CUDA_CHECK(
        cudaFuncSetAttribute(kernel, cudaFuncAttributeMaxDynamicSharedMemorySize, static_cast<int>(shared)));
}

}  // namespace

void launch_fused_per_pixel(const DeviceScene& scene, const TraceLaunch& launch, const ShadingPoint* points,
                            const BsdfParams* materials, uint32_t seed, uint32_t frame, const TileGrid& grid,
                            const FusedBatch& batch, Hit* hits, unsigned long long* stats,
                            const SharedNumbers* shared_numbers) {
  const int block = std::min(256, round_up_warp(grid.tile_w * grid.tile_h));
  const size_t shared = staged_bytes(0, static_cast<uint32_t>(block));
  const auto run = [&](const auto& numbers) {
    with_trace_view(scene, launch, [&](auto view, auto filter) {
      auto kernel = fused_per_pixel_kernel<decltype(view), decltype(filter), std::decay_t<decltype(numbers)>>;
      allow_shared(kernel, shared);
      kernel<<<static_cast<unsigned>(grid.count()), block, shared>>>(view, filter, points, materials, seed, frame, grid,
                                                                     batch, hits, stats, numbers);
    });
  };
  if (shared_numbers)
    run(*shared_numbers);
  else
    run(OwnNumbers{});
  RAYCOH_CUDA_CHECK_LAUNCH();
}

void launch_fused_grouping(const DeviceScene& scene, const TraceLaunch& launch, const GroupingConfig& config,
                           const TileGrid& grid, const ShadingPoint* points, const BsdfParams* materials,
                           const FusedBatch& batch, Hit* hits, unsigned long long* stats) {
  const auto full_m = static_cast<uint32_t>(grid.tile_w * grid.tile_h);
  if (full_m > static_cast<uint32_t>(kMaxGroupTile) || config.k < 1)
    throw Error("cuda: the fused trace groups tiles of at most 1024 pixels with k >= 1");
  if (config.order == RayOrder::Scanline)
    throw Error("cuda: the fused trace makes each tile's rays in its block; order=scanline has no fused form");
  const size_t state = tile_groups_bytes(full_m, (full_m + config.k - 1) / config.k, config.k);
  const auto block = static_cast<uint32_t>(round_up_warp(static_cast<int>(full_m)));
  const size_t shared = staged_bytes(state, block);
  with_trace_view(scene, launch, [&](auto view, auto filter) {
    auto kernel = fused_group_kernel<decltype(view), decltype(filter)>;
    allow_shared(kernel, shared);
    kernel<<<static_cast<unsigned>(grid.count()), block, shared>>>(view, filter, config, grid, points, materials, state,
                                                                   batch, hits, stats);
  });
  RAYCOH_CUDA_CHECK_LAUNCH();
}

}  // namespace raycoh::cuda
