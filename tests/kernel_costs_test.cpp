// The costs of the `cuda` tracer's kernels as the model holds them (simt/gpu_presets.cpp): what one divergent
// node step costs each BVH2 kernel under the L1 rule measured on an H100.
#include <gtest/gtest.h>

#include <string>

#include "simt/gpu_model.h"
#include "tests/node_step_replay.h"

namespace raycoh {
namespace {

// 32 lanes on 32 consecutive 64-byte nodes. Word w of node n is 4-byte word 16 n + 4 w + j: each 16-byte word of
// the record falls in 2 of the 32 banks. Classic: 4-byte loads, one pass of 32 lanes, 16 distinct words in each of
// 2 banks: 16 wavefronts a load, 14 loads + 18 local accesses. Tuned: 16-byte loads in 4 passes of 8 lanes, each
// pass 4 lanes' words in each of 8 banks: 4 wavefronts a pass, 16 a load; 4 loads + 3 local accesses. (The tag
// stage, 16 lines in 4 banks of 4, is below both.)
double divergent_node_l1(TraceKernelChoice kernel) {
  GpuModelConfig g = gpu_preset("h100");
  use_kernel(g, kernel);
  g.cache.sms = 1;
  return test::replay_divergent_node_step(g).l1_busy;
}

TEST(KernelCosts, TheTunedNodeStepTakesFewerH100Wavefronts) {
  const double classic = divergent_node_l1(TraceKernelChoice::Bvh2Classic);
  const double tuned = divergent_node_l1(TraceKernelChoice::Bvh2Tuned);
  // The same ray fetch in both: the difference is the node step's.
  EXPECT_DOUBLE_EQ(classic - tuned, (14 * 16 + 18) - (4 * 16 + 3));
}

// Each preset holds the three kernels; use_kernel takes one and keeps the launch shape the run chose.
TEST(KernelCosts, UseKernelKeepsTheLaunchShape) {
  for (const std::string& name : gpu_preset_names()) {
    SCOPED_TRACE(name);
    GpuModelConfig g = gpu_preset(name);
    EXPECT_EQ(g.kernel.node.global_loads, g.tuned.node.global_loads);  // the default: tuned
    g.kernel.block_threads = 256;
    g.kernel.kind = TraceKernel::Simple;
    use_kernel(g, TraceKernelChoice::Cwbvh);
    EXPECT_EQ(g.kernel.node.global_loads, 5u);
    EXPECT_EQ(g.kernel.block_threads, 256u);
    EXPECT_EQ(g.kernel.kind, TraceKernel::Simple);
    use_kernel(g, TraceKernelChoice::Bvh2Classic);
    EXPECT_EQ(g.kernel.node.global_loads, 14u);
    EXPECT_NO_THROW(validate(g));
  }
}

}  // namespace
}  // namespace raycoh
