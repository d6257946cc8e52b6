// The SIMT warp model of the shared traversal (core/traverse.h): lanes of a warp run the while-while loop of Aila &
// Laine in lock step, and every step's fetches are counted as lines and sectors. The exact stepping and counting
// rules, which a CUDA counting kernel must follow to produce the same counters, are in docs/simt-model.md
// ("Warp stepping" and "Counting rules"). Host only; used by the `simt` tracer and by the tests.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

#include "core/cwbvh.h"
#include "core/error.h"
#include "core/traverse.h"
#include "core/warp_counters.h"
#include "simt/warp_trace.h"
#include "tracers/tracer.h"

namespace raycoh {

constexpr uint32_t kMaxWarpSize = 64;

// Node array at address 0, triangle array at the next 2 MiB boundary after it: the alignment cudaMalloc gives
// large allocations. Throws raycoh::Error for sizes outside the ranges above or sector addresses beyond 32 bits.
SimtConfig simt_config(const BvhView& bvh, uint32_t warp_size, uint32_t line_bytes, uint32_t sector_bytes);
// The same for a CWBVH (80-byte nodes).
SimtConfig simt_config(const CwbvhView& bvh, uint32_t warp_size, uint32_t line_bytes, uint32_t sector_bytes);

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
// A node or triangle (BVH2 64 and 48 bytes, CWBVH 80 bytes) covers at most 4 lines of >= 32 bytes and 5 sectors
// of >= 16 bytes.
constexpr uint32_t kMaxUnitsPerLane = 5;

// The fetches of one step: lines and sectors of the active lanes, made distinct by finish(); and per 16-byte word w
// of the record, each lane's byte address of that word (for the L1 rules that look at a load instruction's
// addresses: WarpTrace::word_cycles).
struct StepFetches {
  uint64_t lines[kMaxWarpSize * kMaxUnitsPerLane];
  uint64_t sectors[kMaxWarpSize * kMaxUnitsPerLane];
  uint64_t words[kMaxRecordWords][kMaxWarpSize];
  uint32_t line_count = 0, sector_count = 0;
  uint32_t word_count[kMaxRecordWords] = {};
  bool words_wanted = false;  // only a trace for the l1_banks or l1_words rule reads them: set from it (for_trace)

  static StepFetches for_trace(const WarpTrace* trace) {
    StepFetches f;
    f.words_wanted = trace && trace->wants_words();
    return f;
  }
  void reset() {
    line_count = sector_count = 0;
    std::fill(word_count, word_count + kMaxRecordWords, 0u);
  }
  void add(uint64_t addr, uint32_t bytes, const SimtConfig& c) {
    for (uint64_t l = addr / c.line_bytes; l <= (addr + bytes - 1) / c.line_bytes; ++l) lines[line_count++] = l;
    for (uint64_t s = addr / c.sector_bytes; s <= (addr + bytes - 1) / c.sector_bytes; ++s) sectors[sector_count++] = s;
    if (!words_wanted) return;
    for (uint32_t w = 0; w < bytes / 16 && w < kMaxRecordWords; ++w) words[w][word_count[w]++] = addr + 16 * w;
  }
  static uint32_t sort_unique(uint64_t* v, uint32_t n) {
    std::sort(v, v + n);
    return static_cast<uint32_t>(std::unique(v, v + n) - v);
  }
  void finish() {
    line_count = sort_unique(lines, line_count);
    sector_count = sort_unique(sectors, sector_count);
  }
  void emit(WarpTrace* trace, SimtStepKind kind) {
    if (!trace) return;
    trace->add_step(kind, sectors, sector_count);
    if (!trace->wants_words()) return;
    for (uint32_t w = 0; w < kMaxRecordWords; ++w) {
      uint32_t cycles = 0;
      if (trace->l1_words) {
        const uint32_t width = kind == SimtStepKind::Node ? trace->node_load_bytes : trace->triangle_load_bytes;
        cycles = word_count[w] ? hopper_l1_cycles(words[w], word_count[w], width) : 0;
      } else {  // GPGPU-Sim's rule by 32-byte sector (the l1_banks presets are checked to have 32-byte sectors)
        for (uint32_t i = 0; i < word_count[w]; ++i) words[w][i] /= 32;
        cycles = l1_bank_cycles(words[w], sort_unique(words[w], word_count[w]), trace->l1_banks);
      }
      trace->word_cycles.back()[w] = static_cast<uint8_t>(cycles);
    }
  }
};

inline uint32_t lanes_in(uint64_t mask) { return static_cast<uint32_t>(std::popcount(mask)); }

// The lanes of `among` whose state satisfies pred.
template <class State, class Pred>
uint64_t lanes_where(const State* st, uint64_t among, Pred&& pred) {
  uint64_t out = 0;
  for (uint64_t m = among; m; m &= m - 1) {
    const int l = std::countr_zero(m);
    if (pred(st[l])) out |= uint64_t{1} << l;
  }
  return out;
}

// Counts one Node or Triangle step of the lanes in `mask` whose fetches f are finished.
inline void count_fetch_step(SimtStepKind kind, uint64_t mask, StepFetches& f, CoherenceCounters& c, WarpTrace* trace,
                             std::vector<SimtStep>* steps) {
  f.emit(trace, kind);
  const bool node = kind == SimtStepKind::Node;
  (node ? c.node_steps : c.triangle_steps) += 1;
  (node ? c.node_lanes : c.triangle_lanes) += lanes_in(mask);
  (node ? c.node_lines : c.triangle_lines) += f.line_count;
  (node ? c.node_fetches : c.triangle_fetches) += f.sector_count;
  if (steps) steps->push_back({kind, mask, f.line_count, f.sector_count});
}

// Counts one Leaf step (no fetch of its own) of the lanes in `mask`.
inline void count_leaf_step(uint64_t mask, CoherenceCounters& c, WarpTrace* trace, std::vector<SimtStep>* steps) {
  c.leaf_steps += 1;
  c.leaf_lanes += lanes_in(mask);
  if (steps) steps->push_back({SimtStepKind::Leaf, mask, 0, 0});
  if (trace) trace->add_step(SimtStepKind::Leaf, nullptr, 0);
}

// The end of a warp: hits, the warp's ray and per-ray counters, and optionally each lane's RayCounters.
template <class State>
void finish_warp(const State* st, const RayCounters* rc, uint32_t lanes, Hit* hits, CoherenceCounters& counters,
                 RayCounters* ray_counters) {
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

}  // namespace simt_detail

// Traces the `lanes` rays of one warp (rays[0 .. lanes), lanes in [1, warp_size]) in lock step under the rules
// of docs/simt-model.md: hits[0 .. lanes) get the closest hits, `counters` accumulates the warp's step and per-ray
// counters (rays, warps, steps, lanes, lines, fetches, nodes, leaves, triangles; not the cache fields). Optional
// outputs: the warp's cache requests, each lane's RayCounters, the step log. `filter` is the any-hit test of alpha
// cut-outs (core/alpha_mask.h); its texel reads are not fetches of the model (they add no lines or sectors).
template <class Filter = NoAlphaTest>
void simt_trace_warp(const BvhView& bvh, const Ray* rays, uint32_t lanes, const SimtConfig& config, Hit* hits,
                     CoherenceCounters& counters, WarpTrace* trace = nullptr, RayCounters* ray_counters = nullptr,
                     std::vector<SimtStep>* steps = nullptr, const Filter& filter = Filter{}) {
  using namespace simt_detail;
  RAYCOH_CHECK(lanes <= kMaxWarpSize && config.line_bytes >= 32 && config.sector_bytes >= 16,
               "simt_trace_warp: more than 64 lanes, or lines/sectors too small for the fetch buffers");
  if (trace) trace->lanes = lanes;
  TraversalState st[kMaxWarpSize];
  RayCounters rc[kMaxWarpSize];
  uint64_t live = 0;  // lanes not done
  for (uint32_t l = 0; l < lanes; ++l) {
    traversal_begin(st[l], rays[l]);
    if (!traversal_done(st[l])) live |= uint64_t{1} << l;
  }
  auto lanes_where = [&](uint64_t among, auto&& pred) { return simt_detail::lanes_where(st, among, pred); };
  StepFetches f = StepFetches::for_trace(trace);
  while (live) {
    // Node loop.
    uint64_t n = lanes_where(live, [](const TraversalState& s) { return traversal_wants_node(s); });
    while (n) {
      f.reset();
      for (uint64_t m = n; m; m &= m - 1) {
        const int l = std::countr_zero(m);
        f.add(config.node_base + uint64_t{kNodeBytes} * static_cast<uint32_t>(st[l].node_ref), kNodeBytes, config);
        node_step(st[l], bvh, rc[l]);
      }
      f.finish();
      count_fetch_step(SimtStepKind::Node, n, f, counters, trace, steps);
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
      count_leaf_step(leaf, counters, trace, steps);
      for (uint32_t j = 0; j < max_count; ++j) {
        f.reset();
        uint64_t sub = 0;
        for (uint64_t m = leaf; m; m &= m - 1) {
          const int l = std::countr_zero(m);
          if (count[l] <= j) continue;
          sub |= uint64_t{1} << l;
          f.add(config.tri_base + uint64_t{kTriBytes} * (first[l] + j), kTriBytes, config);
        }
        f.finish();
        count_fetch_step(SimtStepKind::Triangle, sub, f, counters, trace, steps);
      }
      // The lanes' triangle tests are independent, so running each lane's whole leaf_step in turn computes
      // exactly what the lock-step sub-steps compute.
      for (uint64_t m = leaf; m; m &= m - 1) {
        const int l = std::countr_zero(m);
        leaf_step(st[l], bvh, rc[l], filter);
      }
      leaf = lanes_where(leaf, [](const TraversalState& s) { return traversal_has_leaf(s); });
    }
    live = lanes_where(live, [](const TraversalState& s) { return !traversal_done(s); });
  }
  finish_warp(st, rc, lanes, hits, counters, ray_counters);
}

}  // namespace raycoh
