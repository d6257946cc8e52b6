// One warp's divergent node step replayed by the timing model (simt/timed_replay.h) under a preset's L1 rule:
// 32 lanes on 32 consecutive 64-byte nodes, one SM, the warp's ray fetch included. Shared by the tests that work
// an L1 rule's cost of such a step by hand (tests/gpgpusim_preset_test.cpp, tests/kernel_costs_test.cpp).
#pragma once

#include <gtest/gtest.h>

#include <vector>

#include "simt/gpu_model.h"
#include "simt/simt.h"
#include "simt/timed_replay.h"

namespace raycoh::test {

inline ModeledKernel replay_divergent_node_step(const GpuModelConfig& g) {
  SimtConfig sc;
  sc.line_bytes = 128;
  sc.sector_bytes = 32;
  std::vector<WarpTrace> traces(1);
  traces[0].lanes = 32;
  traces[0].l1_banks = g.gpu.l1_banks;
  traces[0].l1_words = g.gpu.l1_words;
  traces[0].node_load_bytes = g.kernel.node.load_bytes;
  simt_detail::StepFetches f = simt_detail::StepFetches::for_trace(&traces[0]);
  f.reset();
  for (uint64_t n = 0; n < 32; ++n) f.add(64 * n, 64, sc);
  f.finish();
  f.emit(&traces[0], SimtStepKind::Node);
  TimedReplay r(g, 1, 1 << 20);
  r.run(traces, 1);
  EXPECT_TRUE(r.done());
  return r.result();
}

}  // namespace raycoh::test
