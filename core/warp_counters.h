// What the SIMT warp model (simt/simt.h) and the CUDA counting kernel (cuda/trace_kernels.cu) both count, and the
// byte layout they count in: one definition for host and device, so that a counting run on the GPU and the `simt`
// tracer compare field by field. The counting rules are docs/simt-model.md, "Counting rules".
#pragma once

#include <cstdint>

#include "core/platform.h"

namespace raycoh {

// Where the counted arrays sit, and the units steps are counted in. Addresses are offsets in a modelled address
// space: the node array at node_base, the triangle array at tri_base (both multiples of line_bytes and
// sector_bytes), so that lines and sectors follow from indices alone.
struct SimtConfig {
  uint32_t warp_size = 32;     // [1, 64]
  uint32_t line_bytes = 64;    // transaction line, power of two in [32, 4096]
  uint32_t sector_bytes = 32;  // cache-model sector, power of two in [16, 4096]
  uint64_t node_base = 0;      // byte address of nodes[0]
  uint64_t tri_base = 0;       // byte address of tris[0]
};

// The step and per-ray counters of a warp, or of a batch (sums over its warps).
struct WarpStepCounters {
  uint64_t rays = 0;   // rays traced
  uint64_t warps = 0;  // warps (the last of a batch may be partial)
  // Warp steps: iterations of the warp's node loop, of its leaf loop, and triangle iterations inside leaf steps;
  // then the active lanes summed over each kind of step.
  uint64_t node_steps = 0, leaf_steps = 0, triangle_steps = 0;
  uint64_t node_lanes = 0, leaf_lanes = 0, triangle_lanes = 0;
  // Memory transactions: distinct line_bytes lines among the active lanes' fetches, summed over steps.
  uint64_t node_lines = 0, triangle_lines = 0;
  // Cache-model requests: distinct sector_bytes sectors among the active lanes' fetches, summed over steps.
  uint64_t node_fetches = 0, triangle_fetches = 0;
  // Per-ray totals (RayCounters summed over the rays). Equal to the *_lanes sums by construction.
  uint64_t nodes = 0, leaves = 0, triangles = 0;

  RAYCOH_HD void add(const WarpStepCounters& o) {
    rays += o.rays;
    warps += o.warps;
    node_steps += o.node_steps;
    leaf_steps += o.leaf_steps;
    triangle_steps += o.triangle_steps;
    node_lanes += o.node_lanes;
    leaf_lanes += o.leaf_lanes;
    triangle_lanes += o.triangle_lanes;
    node_lines += o.node_lines;
    triangle_lines += o.triangle_lines;
    node_fetches += o.node_fetches;
    triangle_fetches += o.triangle_fetches;
    nodes += o.nodes;
    leaves += o.leaves;
    triangles += o.triangles;
  }
};

}  // namespace raycoh
