// The SIMT warp model of the CWBVH traversal (core/traverse_cwbvh.h), counted with the rules of simt/simt.h so
// that the timing model (simt/timed_replay.h) times it as it times the BVH2 kernel. Host only.
//
// Warp stepping (the loop of Ylitie et al. 2017, each lane's operations in the order of closest_hit_cwbvh()):
//   repeat while some lane is not done:
//     node step    the lanes that want a node (no triangles pending, a node group or a stack entry left) fetch one
//                  80-byte node each: one Node step, its lines and sectors the distinct ones of those lanes;
//     triangles    if some lane holds triangles and either no lane wants a node or at least kCwbvhTriangleShare of
//                  the live lanes hold triangles, one Leaf step (the lanes holding triangles; no fetch: the
//                  triangle group came with the node) and Triangle sub-steps, each testing the next triangle of
//                  every lane that has one left (48-byte fetches), until none has; otherwise the triangles are
//                  postponed and lanes holding them idle through the next node step.
// The postponement is the paper's warp-utilisation heuristic; kCwbvhTriangleShare = 0.2 is our assumption (a
// fixed choice, not fitted to any result).
#pragma once

#include "core/traverse_cwbvh.h"
#include "simt/simt.h"

namespace raycoh {

constexpr double kCwbvhTriangleShare = 0.2;

template <class Filter = NoAlphaTest>
void simt_trace_warp_cwbvh(const CwbvhView& bvh, const Ray* rays, uint32_t lanes, const SimtConfig& config, Hit* hits,
                           CoherenceCounters& counters, WarpTrace* trace = nullptr, RayCounters* ray_counters = nullptr,
                           std::vector<SimtStep>* steps = nullptr, const Filter& filter = Filter{}) {
  using namespace simt_detail;
  RAYCOH_CHECK(lanes <= kMaxWarpSize && config.line_bytes >= 32 && config.sector_bytes >= 16,
               "simt_trace_warp_cwbvh: more than 64 lanes, or lines/sectors too small for the fetch buffers");
  if (trace) trace->lanes = lanes;
  CwbvhState st[kMaxWarpSize];
  RayCounters rc[kMaxWarpSize];
  uint64_t live = 0;
  for (uint32_t l = 0; l < lanes; ++l) {
    cwbvh_begin(st[l], rays[l]);
    if (!cwbvh_done(st[l])) live |= uint64_t{1} << l;
  }
  auto lanes_where = [&](uint64_t among, auto&& pred) { return simt_detail::lanes_where(st, among, pred); };
  constexpr uint32_t kNodeBytes = sizeof(CwbvhNode);
  StepFetches f = StepFetches::for_trace(trace);
  while (live) {
    const uint64_t n = lanes_where(live, [](const CwbvhState& s) { return cwbvh_wants_node(s); });
    if (n) {
      f.reset();
      for (uint64_t m = n; m; m &= m - 1) {
        const int l = std::countr_zero(m);
        const uint32_t index = cwbvh_next_node(st[l]);
        f.add(config.node_base + uint64_t{kNodeBytes} * index, kNodeBytes, config);
        cwbvh_node_step(st[l], bvh, rc[l]);
      }
      f.finish();
      count_fetch_step(SimtStepKind::Node, n, f, counters, trace, steps);
    }
    uint64_t tri = lanes_where(live, [](const CwbvhState& s) { return cwbvh_has_triangles(s); });
    const uint64_t wanting = lanes_where(live, [](const CwbvhState& s) { return cwbvh_wants_node(s); });
    const uint64_t still = lanes_where(live, [](const CwbvhState& s) { return !cwbvh_done(s); });
    if (tri && (wanting == 0 || lanes_in(tri) >= kCwbvhTriangleShare * lanes_in(still))) {
      count_leaf_step(tri, counters, trace, steps);
      for (uint64_t m = tri; m; m &= m - 1) rc[std::countr_zero(m)].on_leaf(0);
      while (tri) {
        f.reset();
        for (uint64_t m = tri; m; m &= m - 1) {
          const int l = std::countr_zero(m);
          const uint32_t i = st[l].tri_base + lowest_bit(st[l].tri_hits);
          f.add(config.tri_base + uint64_t{sizeof(BvhTriangle)} * i, sizeof(BvhTriangle), config);
          cwbvh_triangle_step(st[l], bvh, rc[l], filter);
        }
        f.finish();
        count_fetch_step(SimtStepKind::Triangle, tri, f, counters, trace, steps);
        tri = lanes_where(tri, [](const CwbvhState& s) { return cwbvh_has_triangles(s); });
      }
    }
    live = still;
  }
  finish_warp(st, rc, lanes, hits, counters, ray_counters);
}

}  // namespace raycoh
