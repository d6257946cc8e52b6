// The SIMT warp model of the shared traversal (core/traverse.h), and the counting rules a CUDA counting kernel
// must follow to produce the same counters. Host only; used by the `simt` tracer and by the tests.
//
// A warp is `warp_size` (default 32) consecutive rays of the batch, lane i = ray (warp * warp_size + i); the last
// warp of a batch may have fewer lanes, and the missing lanes are never active. Lanes run the while-while loop
// of Aila & Laine ("Understanding the Efficiency of Ray Traversal on GPUs", HPG 2009) in lock step, calling
// traversal_begin / node_step / leaf_step unchanged:
//
//   all lanes: traversal_begin                  (rejected rays are done at once and never active)
//   while any lane !traversal_done:
//     N = lanes with traversal_wants_node                       -- node loop
//     while N not empty:
//       NODE STEP: every lane of N runs node_step
//       if every lane of N now traversal_has_leaf: break        -- Aila's `if (!__any(leafAddr >= 0)) break;`
//       N = lanes of N with traversal_wants_node
//     L = lanes with traversal_has_leaf                         -- leaf loop
//     while L not empty:
//       LEAF STEP: every lane of L runs leaf_step; its triangle loop runs in lock step as TRIANGLE SUB-STEPS
//                  j = 0 .. max count - 1, sub-step j active on the lanes of L whose leaf has more than j triangles
//       L = lanes of L with traversal_has_leaf
//
// So a lane that already holds a leaf keeps walking nodes while some other lane of N has none (and may postpone
// a second leaf in node_ref, which ends its node walk); the break looks only at the lanes that stepped. With a
// warp of one lane this is exactly closest_hit(), counters included. With wider warps the per-ray node counts
// depend on the warp's other rays (speculative node fetches), the hits do not: they equal closest_hit()'s.
//
// Counting rules (per warp; the tracer sums them over the batch into CoherenceCounters):
//   1. node step: node_steps += 1, node_lanes += |N|. Lane l fetches bytes [node_base + 64 * node_ref_l, +64).
//   2. leaf step: leaf_steps += 1, leaf_lanes += |L|. A leaf step itself fetches nothing (the leaf reference
//      came with its parent node).
//   3. triangle sub-step j: triangle_steps += 1, triangle_lanes += active lanes; lane l fetches bytes
//      [tri_base + 48 * (first_l + j), +48), which may straddle two lines: both count.
//   4. transactions: node_lines / triangle_lines += number of distinct line_bytes lines in the union of the
//      byte ranges the step's active lanes fetch (line = address / line_bytes).
//   5. cache requests: node_fetches / triangle_fetches += number of distinct sector_bytes sectors in that union;
//      those sectors, in ascending order, are the step's request to the cache model (simt/cache_model.h).
//   6. per ray: RayCounters (nodes, leaves, triangles) of each lane, summed; they equal the *_lanes sums.
//   7. SIMT efficiency: active lanes / (warp_size x steps), node and leaf steps pooled (simt_efficiency()) and
//      each kind alone; a partial last warp counts its missing lanes as idle, as a GPU would.
//   Addresses are offsets inside each array (bases are line- and sector-aligned), so a CUDA kernel computes the
//   same lines from indices alone: line = (index * size) / line_bytes for the first and (index * size + size - 1)
//   / line_bytes for the last byte.
//
// Reproducing it in CUDA (warp_size 32; other sizes are a model only). Keep every loop warp-uniform with explicit
// masks (__ballot_sync(0xffffffff, ...) evaluated by all 32 lanes; threads past the end of the batch stay in the
// loops with false predicates instead of returning), never __activemask(): under independent thread scheduling
// the converged set is not guaranteed, and the rules above need exactly N and L. The node-loop break is
// `if ((__ballot_sync(full, has_leaf) & N) == N) break;`. Count a step from node_ref / leaf_ref before calling
// node_step / leaf_step, as simt_trace_warp does, so that the traversal functions stay unchanged: the triangle
// sub-steps of a leaf step are j = 0 .. the warp's maximum count - 1 (__reduce_max_sync) with mask
// __ballot_sync(full, in_L && j < count), counted before the lanes run leaf_step. Node transactions with
// line_bytes >= 64: one line per lane, so `m = __match_any_sync(mask, line)` and the lanes with
// `lane == __ffs(m) - 1` are the distinct lines (popc of their ballot). Triangle transactions: a lane's range
// covers line a and, when it straddles, a + 1; count the union exactly with the same leader trick on a, then
// for each straddling lane test its a + 1 against every active lane's a (32 __shfl_sync) and against the other
// straddling lanes' a + 1 (a second __match_any_sync among the straddlers whose a + 1 is new). Counting runs only.
//
// Modeled cost (modeled_cost() below; weights in CostWeights, simt/cache_model.h, with their sources):
//   cost = node_step x node_steps + leaf_step x leaf_steps + triangle_step x triangle_steps
//        + l1_hit x l1_hits + l2_hit x l2_hits + dram x l2_misses                            [cycles]
// The step terms are issue slots (instructions a warp executes whatever its active lanes: what divergence
// wastes); the memory terms weigh each sector by the latency of the level that served it (what incoherence
// costs). It is a ranking model for comparing batch orders and methods on one configuration: it ignores latency
// hiding by other warps, bandwidth limits, queueing and overlap, so it does not predict a time.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

#include "core/error.h"
#include "core/traverse.h"
#include "simt/cache_model.h"
#include "tracers/tracer.h"

namespace raycoh {

constexpr uint32_t kMaxWarpSize = 64;

struct SimtConfig {
  uint32_t warp_size = 32;     // [1, 64]
  uint32_t line_bytes = 64;    // transaction line, power of two in [32, 4096]
  uint32_t sector_bytes = 32;  // cache-model sector, power of two in [16, 4096]
  uint64_t node_base = 0;      // byte address of nodes[0], multiple of line_bytes and sector_bytes
  uint64_t tri_base = 0;       // byte address of tris[0], same
};

// Node array at address 0, triangle array at the next 2 MiB boundary after it: the alignment cudaMalloc gives
// large allocations. Throws raycoh::Error for sizes outside the ranges above or sector addresses beyond 32 bits.
SimtConfig simt_config(const BvhView& bvh, uint32_t warp_size, uint32_t line_bytes, uint32_t sector_bytes);

enum class SimtStepKind : uint8_t { Node, Leaf, Triangle };

// One step of a warp, for tests and for comparing with a CUDA counting run step by step.
struct SimtStep {
  SimtStepKind kind;
  uint64_t active;   // lane mask
  uint32_t lines;    // transactions (0 for leaf steps)
  uint32_t sectors;  // cache-model request size (0 for leaf steps)
};

namespace simt_detail {

constexpr uint32_t kNodeBytes = sizeof(BvhNode);
constexpr uint32_t kTriBytes = sizeof(BvhTriangle);
// A node or triangle covers at most 3 lines of >= 32 bytes and 4 sectors of >= 16 bytes.
constexpr uint32_t kMaxUnitsPerLane = 4;

// The fetches of one step: lines and sectors of the active lanes, made distinct by finish().
struct StepFetches {
  uint64_t lines[kMaxWarpSize * kMaxUnitsPerLane];
  uint64_t sectors[kMaxWarpSize * kMaxUnitsPerLane];
  uint32_t line_count = 0, sector_count = 0;

  void add(uint64_t addr, uint32_t bytes, const SimtConfig& c) {
    for (uint64_t l = addr / c.line_bytes; l <= (addr + bytes - 1) / c.line_bytes; ++l) lines[line_count++] = l;
    for (uint64_t s = addr / c.sector_bytes; s <= (addr + bytes - 1) / c.sector_bytes; ++s) sectors[sector_count++] = s;
  }
  static uint32_t sort_unique(uint64_t* v, uint32_t n) {
    std::sort(v, v + n);
    return static_cast<uint32_t>(std::unique(v, v + n) - v);
  }
  void finish() {
    line_count = sort_unique(lines, line_count);
    sector_count = sort_unique(sectors, sector_count);
  }
  void emit(WarpTrace* trace) const {
    if (!trace) return;
    for (uint32_t i = 0; i < sector_count; ++i) trace->sectors.push_back(static_cast<uint32_t>(sectors[i]));
    trace->request_end.push_back(static_cast<uint32_t>(trace->sectors.size()));
  }
};

inline uint32_t lanes_in(uint64_t mask) { return static_cast<uint32_t>(std::popcount(mask)); }

}  // namespace simt_detail

// Traces the `lanes` rays of one warp (rays[0 .. lanes), lanes in [1, warp_size]) in lock step under the rules
// above: hits[0 .. lanes) get the closest hits, `counters` accumulates the warp's step and per-ray counters
// (rays, warps, steps, lanes, lines, fetches, nodes, leaves, triangles; not the cache fields). Optional outputs:
// the warp's cache requests, each lane's RayCounters, the step log.
inline void simt_trace_warp(const BvhView& bvh, const Ray* rays, uint32_t lanes, const SimtConfig& config, Hit* hits,
                            CoherenceCounters& counters, WarpTrace* trace = nullptr,
                            RayCounters* ray_counters = nullptr, std::vector<SimtStep>* steps = nullptr) {
  using namespace simt_detail;
  RAYCOH_CHECK(lanes <= kMaxWarpSize && config.line_bytes >= 32 && config.sector_bytes >= 16,
               "simt_trace_warp: more than 64 lanes, or lines/sectors too small for the fetch buffers");
  TraversalState st[kMaxWarpSize];
  RayCounters rc[kMaxWarpSize];
  uint64_t live = 0;  // lanes not done
  for (uint32_t l = 0; l < lanes; ++l) {
    traversal_begin(st[l], rays[l]);
    if (!traversal_done(st[l])) live |= uint64_t{1} << l;
  }
  auto lanes_where = [&](uint64_t among, auto&& pred) {
    uint64_t out = 0;
    for (uint64_t m = among; m; m &= m - 1) {
      const int l = std::countr_zero(m);
      if (pred(st[l])) out |= uint64_t{1} << l;
    }
    return out;
  };
  StepFetches f;
  while (live) {
    // Node loop.
    uint64_t n = lanes_where(live, [](const TraversalState& s) { return traversal_wants_node(s); });
    while (n) {
      f.line_count = f.sector_count = 0;
      for (uint64_t m = n; m; m &= m - 1) {
        const int l = std::countr_zero(m);
        f.add(config.node_base + uint64_t{kNodeBytes} * static_cast<uint32_t>(st[l].node_ref), kNodeBytes, config);
        node_step(st[l], bvh, rc[l]);
      }
      f.finish();
      f.emit(trace);
      counters.node_steps += 1;
      counters.node_lanes += lanes_in(n);
      counters.node_lines += f.line_count;
      counters.node_fetches += f.sector_count;
      if (steps) steps->push_back({SimtStepKind::Node, n, f.line_count, f.sector_count});
      if (lanes_where(n, [](const TraversalState& s) { return traversal_has_leaf(s); }) == n) break;
      n = lanes_where(n, [](const TraversalState& s) { return traversal_wants_node(s); });
    }
    // Leaf loop.
    uint64_t leaf = lanes_where(live, [](const TraversalState& s) { return traversal_has_leaf(s); });
    while (leaf) {
      uint32_t first[kMaxWarpSize], count[kMaxWarpSize], max_count = 0;
      for (uint64_t m = leaf; m; m &= m - 1) {
        const int l = std::countr_zero(m);
        first[l] = leaf_first(st[l].leaf_ref);
        count[l] = leaf_count(st[l].leaf_ref);
        max_count = std::max(max_count, count[l]);
      }
      counters.leaf_steps += 1;
      counters.leaf_lanes += lanes_in(leaf);
      if (steps) steps->push_back({SimtStepKind::Leaf, leaf, 0, 0});
      for (uint32_t j = 0; j < max_count; ++j) {
        f.line_count = f.sector_count = 0;
        uint64_t sub = 0;
        for (uint64_t m = leaf; m; m &= m - 1) {
          const int l = std::countr_zero(m);
          if (count[l] <= j) continue;
          sub |= uint64_t{1} << l;
          f.add(config.tri_base + uint64_t{kTriBytes} * (first[l] + j), kTriBytes, config);
        }
        f.finish();
        f.emit(trace);
        counters.triangle_steps += 1;
        counters.triangle_lanes += lanes_in(sub);
        counters.triangle_lines += f.line_count;
        counters.triangle_fetches += f.sector_count;
        if (steps) steps->push_back({SimtStepKind::Triangle, sub, f.line_count, f.sector_count});
      }
      // The lanes' triangle tests are independent, so running each lane's whole leaf_step in turn computes
      // exactly what the lock-step sub-steps compute.
      for (uint64_t m = leaf; m; m &= m - 1) {
        const int l = std::countr_zero(m);
        leaf_step(st[l], bvh, rc[l]);
      }
      leaf = lanes_where(leaf, [](const TraversalState& s) { return traversal_has_leaf(s); });
    }
    live = lanes_where(live, [](const TraversalState& s) { return !traversal_done(s); });
  }
  counters.rays += lanes;
  counters.warps += 1;
  for (uint32_t l = 0; l < lanes; ++l) {
    hits[l] = st[l].hit;
    counters.nodes += rc[l].nodes;
    counters.leaves += rc[l].leaves;
    counters.triangles += rc[l].triangles;
    if (ray_counters) ray_counters[l] = rc[l];
  }
}

// Adds the step and per-ray fields of `warp` (what simt_trace_warp accumulates) into `total`.
inline void add_warp_counters(CoherenceCounters& total, const CoherenceCounters& warp) {
  total.rays += warp.rays;
  total.warps += warp.warps;
  total.node_steps += warp.node_steps;
  total.leaf_steps += warp.leaf_steps;
  total.triangle_steps += warp.triangle_steps;
  total.node_lanes += warp.node_lanes;
  total.leaf_lanes += warp.leaf_lanes;
  total.triangle_lanes += warp.triangle_lanes;
  total.node_lines += warp.node_lines;
  total.triangle_lines += warp.triangle_lines;
  total.node_fetches += warp.node_fetches;
  total.triangle_fetches += warp.triangle_fetches;
  total.nodes += warp.nodes;
  total.leaves += warp.leaves;
  total.triangles += warp.triangles;
}

inline double modeled_cost(const CoherenceCounters& c, const CostWeights& w) {
  return w.node_step * static_cast<double>(c.node_steps) + w.leaf_step * static_cast<double>(c.leaf_steps) +
         w.triangle_step * static_cast<double>(c.triangle_steps) + w.l1_hit * static_cast<double>(c.l1_hits) +
         w.l2_hit * static_cast<double>(c.l2_hits) + w.dram * static_cast<double>(c.l2_misses);
}

}  // namespace raycoh
