// The warp-synchronous counting kernel behind cuda/counting_kernel.h.
//
// Counting (simt/simt.h, "Reproducing it in CUDA"): every loop is warp-uniform with explicit masks from
// __ballot_sync over all 32 lanes (lanes past the end of the batch stay in the loops with false predicates), the
// node-loop break is `(ballot(has_leaf) & N) == N`, steps are counted from node_ref / leaf_ref before
// node_step / leaf_step run, and the triangle sub-steps of a leaf step are j = 0 .. __reduce_max_sync(count) - 1.
// Distinct lines and sectors of a step are counted exactly as the size of the union of the lanes' unit ranges:
// a unit of lane i counts unless a lower active lane's range covers it (32 __shfl_sync rounds per step). This is
// one rule for nodes and triangles, for any line and sector size, including triangles straddling two lines.
//
#include <cuda_runtime.h>

#include "core/traverse.h"
#include "cuda/counting_kernel.h"
#include "cuda/ray_io.cuh"

namespace raycoh::cuda {

namespace {

constexpr unsigned kFullMask = 0xffffffffu;
constexpr int kWarp = 32;

// Size of the union of the unit ranges [first, last] of the active lanes (last - first < 32); all 32 lanes call it.
// Each unit of a lane counts once, unless a lower active lane covers it: the union is counted exactly once.
__device__ __forceinline__ uint32_t distinct_units(bool active, uint32_t first, uint32_t last) {
  const unsigned lane = threadIdx.x & (kWarp - 1);
  const uint32_t span = active ? last - first + 1u : 0u;
  uint32_t covered = 0;  // bit k: unit first + k is covered by a lower active lane
  for (int j = 0; j < kWarp; ++j) {
    const uint32_t first_j = __shfl_sync(kFullMask, first, j);
    const uint32_t span_j = __shfl_sync(kFullMask, span, j);
    if (static_cast<unsigned>(j) < lane && span_j > 0) {
      const uint32_t last_j = first_j + (span_j - 1u);
      for (uint32_t k = 0; k < span; ++k) {
        const uint32_t u = first + k;
        if (first_j <= u && u <= last_j) covered |= 1u << k;
      }
    }
  }
  const uint32_t own = span - static_cast<uint32_t>(__popc(covered));
  return __reduce_add_sync(kFullMask, own);
}

// Distinct lines (or sectors) of `unit` bytes among the active lanes' byte ranges [addr, addr + bytes). One call
// site for all lanes: the shuffles inside must be reached by the whole warp at the same instruction.
__device__ __forceinline__ uint32_t units_of(bool active, uint64_t addr, uint32_t bytes, uint32_t unit) {
  const auto first = static_cast<uint32_t>(addr / unit);
  const auto last = static_cast<uint32_t>((addr + bytes - 1) / unit);
  return distinct_units(active, first, last);
}

template <bool Indirect, class Filter>
__global__ void counting_kernel(BvhView bvh, Filter filter, const Ray* rays, const uint32_t* order, size_t count,
                                Hit* hits, SimtConfig layout, WarpStepCounters* out, size_t warps) {
  // A whole warp leaves together here: blockDim.x is a multiple of 32.
  const size_t warp = (blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x) / kWarp;
  if (warp >= warps) return;
  const unsigned lane = threadIdx.x & (kWarp - 1);
  const unsigned lane_bit = 1u << lane;
  const size_t i = warp * kWarp + lane;
  const bool valid = i < count;

  Ray r;  // lanes past the end get an empty interval: traversal_begin marks them done at once
  r.tmax = 0.f;
  if (valid) r = load_ray(rays, Indirect ? order[i] : i);
  TraversalState st;
  traversal_begin(st, r);
  RayCounters rc;
  WarpStepCounters c;
  c.warps = 1;
  constexpr uint32_t kNodeBytes = sizeof(BvhNode), kTriBytes = sizeof(BvhTriangle);

  unsigned live = __ballot_sync(kFullMask, valid && !traversal_done(st));
  while (live) {
    // Node loop.
    unsigned n = __ballot_sync(kFullMask, (live & lane_bit) && traversal_wants_node(st));
    while (n) {
      const bool in_n = (n & lane_bit) != 0;
      const uint64_t addr = layout.node_base + uint64_t{kNodeBytes} * static_cast<uint32_t>(in_n ? st.node_ref : 0);
      c.node_steps += 1;
      c.node_lanes += static_cast<uint32_t>(__popc(n));
      c.node_lines += units_of(in_n, addr, kNodeBytes, layout.line_bytes);
      c.node_fetches += units_of(in_n, addr, kNodeBytes, layout.sector_bytes);
      if (in_n) node_step(st, bvh, rc);
      if (__ballot_sync(kFullMask, in_n && traversal_has_leaf(st)) == n) break;
      n = __ballot_sync(kFullMask, in_n && traversal_wants_node(st));
    }
    // Leaf loop.
    unsigned l = __ballot_sync(kFullMask, (live & lane_bit) && traversal_has_leaf(st));
    while (l) {
      const bool in_l = (l & lane_bit) != 0;
      const uint32_t first = in_l ? leaf_first(st.leaf_ref) : 0u;
      const uint32_t tri_count = in_l ? leaf_count(st.leaf_ref) : 0u;
      const uint32_t max_count = __reduce_max_sync(kFullMask, tri_count);
      c.leaf_steps += 1;
      c.leaf_lanes += static_cast<uint32_t>(__popc(l));
      for (uint32_t j = 0; j < max_count; ++j) {
        const bool in_sub = in_l && j < tri_count;
        const unsigned sub = __ballot_sync(kFullMask, in_sub);
        const uint64_t addr = layout.tri_base + uint64_t{kTriBytes} * (in_sub ? first + j : 0u);
        c.triangle_steps += 1;
        c.triangle_lanes += static_cast<uint32_t>(__popc(sub));
        c.triangle_lines += units_of(in_sub, addr, kTriBytes, layout.line_bytes);
        c.triangle_fetches += units_of(in_sub, addr, kTriBytes, layout.sector_bytes);
      }
      if (in_l) leaf_step(st, bvh, rc, filter);
      l = __ballot_sync(kFullMask, in_l && traversal_has_leaf(st));
    }
    live = __ballot_sync(kFullMask, valid && !traversal_done(st));
  }

  c.rays = static_cast<uint32_t>(__popc(__ballot_sync(kFullMask, valid)));
  c.nodes = __reduce_add_sync(kFullMask, rc.nodes);
  c.leaves = __reduce_add_sync(kFullMask, rc.leaves);
  c.triangles = __reduce_add_sync(kFullMask, rc.triangles);
  if (valid) store_hit(hits, i, st.hit);
  if (lane == 0) out[warp] = c;
}

template <class Filter>
void launch_counting_with(const BvhView& bvh, const Filter& filter, unsigned blocks, int block, const Ray* rays,
                          const uint32_t* order, size_t count, Hit* hits, const SimtConfig& layout,
                          WarpStepCounters* out, size_t warps) {
  if (order)
    counting_kernel<true><<<blocks, block>>>(bvh, filter, rays, order, count, hits, layout, out, warps);
  else
    counting_kernel<false><<<blocks, block>>>(bvh, filter, rays, nullptr, count, hits, layout, out, warps);
}

}  // namespace

void launch_counting(const BvhView& bvh, const NoAlphaTest& filter, unsigned blocks, int block, const Ray* rays,
                     const uint32_t* order, size_t count, Hit* hits, const SimtConfig& layout, WarpStepCounters* out,
                     size_t warps) {
  launch_counting_with(bvh, filter, blocks, block, rays, order, count, hits, layout, out, warps);
}
void launch_counting(const BvhView& bvh, const AlphaTest& filter, unsigned blocks, int block, const Ray* rays,
                     const uint32_t* order, size_t count, Hit* hits, const SimtConfig& layout, WarpStepCounters* out,
                     size_t warps) {
  launch_counting_with(bvh, filter, blocks, block, rays, order, count, hits, layout, out, warps);
}

}  // namespace raycoh::cuda
