// The `simt` preset that mirrors GPGPU-Sim's RTX 3070 (simt/gpu_presets.cpp, gpgpusim_rtx3070): its values, the
// simulator's occupancy rule, and, where the simulator is set up (RAYCOH_GPGPUSIM_DIR), that every cited line of
// its configuration file holds the cited option and value.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "simt/cache_model.h"
#include "simt/gpu_model.h"
#include "simt/simt.h"
#include "simt/timed_replay.h"
#include "tests/node_step_replay.h"

namespace raycoh {
namespace {

TEST(GpgpusimPreset, MirrorsTheSimulatorsRtx3070) {
  const GpuModelConfig g = gpu_preset("gpgpusim-rtx3070");
  EXPECT_EQ(g.preset, "gpgpusim-rtx3070");
  EXPECT_EQ(g.cache.sms, 46u);
  EXPECT_DOUBLE_EQ(g.gpu.clock_mhz, 1132.0);
  EXPECT_EQ(g.gpu.max_warps_per_sm, 48u);
  EXPECT_EQ(g.gpu.max_blocks_per_sm, 32u);
  EXPECT_EQ(g.gpu.schedulers_per_sm, 4u);
  EXPECT_EQ(g.cache.l1.bytes, 128u * 1024);
  EXPECT_EQ(g.cache.l2.bytes, 4u * 1024 * 1024);
  EXPECT_EQ(g.cache.line_bytes, 128u);
  EXPECT_EQ(g.cache.sector_bytes, 32u);
  EXPECT_EQ(SectoredLruCache(g.cache.l1.bytes, g.cache.l1.ways, 128, 32).sets(), 4u);  // S:4:128:256
  EXPECT_EQ(g.cache.l2.ways, 16u);
  EXPECT_DOUBLE_EQ(g.gpu.l2_bytes_per_clk, 1024.0);
  EXPECT_NEAR(g.gpu.dram_gb_s, 448.06, 0.01);
  EXPECT_DOUBLE_EQ(g.gpu.l1_latency, 39.0);
  EXPECT_DOUBLE_EQ(g.gpu.l2_latency, 187.0);
  EXPECT_DOUBLE_EQ(g.gpu.dram_latency, 441.0);
  EXPECT_DOUBLE_EQ(g.gpu.launch_cycles, 5000.0);
  EXPECT_EQ(g.gpu.l1_banks, 4u);
  EXPECT_DOUBLE_EQ(g.classic.node.issue_cycles, 146.0);  // PTX (scripts/count-ptx-step-instructions), not SASS
  EXPECT_EQ(g.classic.node.local_accesses, 23u);
  EXPECT_DOUBLE_EQ(g.classic.triangle.issue_cycles, 134.0);
  EXPECT_DOUBLE_EQ(g.classic.node.inorder_cycles, 1242.0);  // in-order PTX issue, L1 hits
  // The kernel modelled by default is the tuned one: its own PTX counts (probe_wide_*).
  EXPECT_DOUBLE_EQ(g.kernel.node.issue_cycles, 95.0);
  EXPECT_EQ(g.kernel.node.global_loads, 4u);
  EXPECT_EQ(g.kernel.node.load_bytes, 16u);
  EXPECT_DOUBLE_EQ(g.kernel.node.inorder_cycles, 331.0);
  EXPECT_DOUBLE_EQ(gpu_preset("h100").kernel.node.inorder_cycles, 0.0);      // ptxas schedules SASS
  EXPECT_DOUBLE_EQ(gpu_preset("rtx3060").classic.node.issue_cycles, 115.0);  // SASS
  EXPECT_DOUBLE_EQ(gpu_preset("rtx3060").kernel.node.issue_cycles, 98.0);    // SASS of the tuned kernel
  // cfg:94; the hardware presets keep the tag rule
  EXPECT_EQ(gpu_preset("rtx3060").gpu.l1_banks, 0u);
  EXPECT_EQ(gpu_preset("h100").gpu.l1_banks, 0u);
  EXPECT_DOUBLE_EQ(gpu_preset("rtx3060").gpu.launch_cycles, 0.0);  // no published figure for the hardware
  EXPECT_DOUBLE_EQ(gpu_preset("h100").gpu.launch_cycles, 0.0);
  EXPECT_NO_THROW(validate(g));
}

// The launch latency is a constant before the first block: it adds to the kernel's cycles and nothing else.
TEST(GpgpusimPreset, LaunchLatencyAddsToTheKernelTime) {
  auto run = [](double launch) {
    GpuModelConfig g = gpu_preset("gpgpusim-rtx3070");
    g.cache.sms = 2;
    g.gpu.launch_cycles = launch;
    std::vector<WarpTrace> traces(100);
    for (size_t w = 0; w < traces.size(); ++w) {
      traces[w].lanes = 32;
      traces[w].l1_banks = g.gpu.l1_banks;
      for (uint64_t s = 0; s < 6; ++s) {
        const uint64_t sector = (w * 7 + s * 131) % 4096;
        traces[w].add_step(SimtStepKind::Node, &sector, 1);
      }
    }
    TimedReplay r(g, traces.size(), 1 << 20);
    r.run(traces, traces.size());
    EXPECT_TRUE(r.done());
    return r.result();
  };
  const ModeledKernel a = run(0), b = run(5000);
  EXPECT_GT(a.cycles, 0.0);
  EXPECT_DOUBLE_EQ(b.cycles, a.cycles + 5000);
  EXPECT_DOUBLE_EQ(b.ms, b.cycles / 1132e3);
  EXPECT_DOUBLE_EQ(b.issue_busy, a.issue_busy);
}

// ldst_unit::process_memory_access_queue_l1cache: from the highest sector down, up to 4 a cycle, a cycle ends at
// the first repeated bank (sector mod 4).
TEST(GpgpusimPreset, L1BankCyclesFollowTheSimulatorsQueue) {
  auto cycles = [](std::vector<uint64_t> s) { return l1_bank_cycles(s.data(), static_cast<uint32_t>(s.size()), 4); };
  EXPECT_EQ(cycles({}), 0u);
  EXPECT_EQ(cycles({7}), 1u);
  EXPECT_EQ(cycles({0, 1, 2, 3}), 1u);     // a coalesced 128-byte line
  EXPECT_EQ(cycles({0, 1, 2, 3, 4}), 2u);  // 4(b0) 3 2 1 | 0
  EXPECT_EQ(cycles({0, 4, 8}), 3u);        // one bank
  EXPECT_EQ(cycles({0, 2, 4, 6}), 2u);     // 6(b2) 4(b0) | 2(b2) 0(b0)
  EXPECT_EQ(cycles({0, 1, 5, 6}), 2u);     // 6(b2) 5(b1) | 1(b1) 0(b0): the order matters, not the set
  std::vector<uint64_t> line32;
  for (uint64_t i = 0; i < 32; ++i) line32.push_back(i);
  EXPECT_EQ(cycles(line32), 8u);
  EXPECT_EQ(l1_bank_cycles(line32.data(), 32, 1), 32u);
}

// One warp, one node step of 32 lanes on 32 consecutive 64-byte nodes: each load's 32 sectors fall in 2 banks
// (a node's words 0-1 in sector 2n, words 2-3 in 2n + 1), 2 a cycle: 16 cycles x 14 loads, where the tag rule
// takes ceil(16 lines / 4) = 4 x 14. Plus the local accesses, and the ray fetch: 2 loads of 32 consecutive
// sectors, 8 cycles each (tag rule: 512 bytes through 128 bytes a cycle, 4 each).
TEST(GpgpusimPreset, TheBankRuleTakesALoadsSectorsFourBanksAtATime) {
  GpuModelConfig g = gpu_preset("gpgpusim-rtx3070");
  use_kernel(g, TraceKernelChoice::Bvh2Classic);  // 14 four-byte loads a node step
  g.cache.sms = 1;
  g.gpu.launch_cycles = 0;
  auto run = [&](uint32_t banks) {
    g.gpu.l1_banks = banks;
    return test::replay_divergent_node_step(g);
  };
  const double local = g.kernel.node.local_accesses;  // 23 (PTX)
  EXPECT_DOUBLE_EQ(run(4).l1_busy, 16 + 14 * 16 + local);
  EXPECT_DOUBLE_EQ(run(0).l1_busy, 8 + 14 * 4 + local);
  g.gpu.l1_banks = 3;
  EXPECT_THROW(validate(g), Error);
  g.gpu.l1_banks = 4;
  g.kernel.node.word_loads = {4, 4, 4, 1, 0};  // 13, not the node's 14 loads
  EXPECT_THROW(validate(g), Error);
}

TEST(GpgpusimPreset, OccupancyFollowsTheSimulatorsRegisterRounding) {
  GpuModelConfig g = gpu_preset("gpgpusim-rtx3070");
  EXPECT_EQ(resident_warps(g), 36u);  // 55 -> 56 registers: 65536 / (128 x 56) = 9 blocks of 4 warps
  g.kernel.regs_per_thread = 41;      // 44 per thread: 11 blocks (a 256-register unit per warp would give 10)
  EXPECT_EQ(resident_warps(g), 44u);
  g.kernel.regs_per_thread = 16;
  EXPECT_EQ(resident_warps(g), 48u);  // 1536 threads per SM
}

// The cited lines (simt/gpu_presets.cpp, "cfg:LINE") of configs/tested-cfgs/SM86_RTX3070/gpgpusim.config.
TEST(GpgpusimPreset, CitedConfigLinesHoldTheValues) {
  const char* dir = std::getenv("RAYCOH_GPGPUSIM_DIR");
  const std::string path = std::string(dir ? dir : "") + "/gpgpu-sim/configs/tested-cfgs/SM86_RTX3070/gpgpusim.config";
  std::ifstream in(path);
  if (!dir || !in) GTEST_SKIP() << "no simulator configuration at " << path;
  std::vector<std::string> lines(1);  // 1-based
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  const std::vector<std::pair<size_t, std::string>> cited = {
      {11, "-gpgpu_kernel_launch_latency 5000"},
      {12, "-gpgpu_TB_launch_latency 0"},
      {24, "-gpgpu_n_clusters 46"},
      {25, "-gpgpu_n_cores_per_cluster 1"},
      {26, "-gpgpu_n_mem 16"},
      {27, "-gpgpu_n_sub_partition_per_mchannel 2"},
      {31, "-gpgpu_clock_domains 1132:1132:1132:3500.5"},
      {34, "-gpgpu_shader_registers 65536"},
      {38, "-gpgpu_shader_core_pipeline 1536:32"},
      {39, "-gpgpu_shader_cta 32"},
      {79, "-gpgpu_num_sched_per_core 4"},
      {82, "-gpgpu_max_insn_issue_per_warp 1"},
      {90, "-gpgpu_adaptive_cache_config 1"},
      {92, "-gpgpu_unified_l1d_size 128"},
      {94, "-gpgpu_l1_banks 4"},
      {95, "-gpgpu_cache:dl1 S:4:128:256,"},
      {96, "-gpgpu_l1_latency 39"},
      {114, "-gpgpu_cache:dl2 S:64:128:16,"},
      {140, "-gpgpu_l2_rop_latency 187"},
      {141, "-dram_latency 254"},
      {149, "-gpgpu_n_mem_per_ctrlr 1"},
      {150, "-gpgpu_dram_buswidth 2"},
      {152, "-dram_data_command_freq_ratio 4"},
  };
  for (const auto& [line, text] : cited) {
    ASSERT_LT(line, lines.size()) << path;
    EXPECT_EQ(lines[line].rfind(text, 0), 0u) << path << ":" << line << " is '" << lines[line] << "'";
  }
}

}  // namespace
}  // namespace raycoh
