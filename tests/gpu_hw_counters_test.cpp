// `cuda:counters=hw` on a device (label `gpu`; skips without one). On a real GPU: CUPTI reads the trace kernels'
// counters, every row carries run_under cupti-counters and plausible measured values (hit rates and utilisations
// in [0, 100], instructions, wavefronts and L2 bytes per ray above 0), on the BVH2 and CWBVH kernels and on the
// device and host pipelines. Under GPGPU-Sim: the one not-available line, and the run otherwise unchanged.
#include <gtest/gtest.h>

#include <string>

#include "cuda/cuda_device.h"
#include "cuda/hw_profiler.h"
#include "records/hw_columns.h"
#include "tests/cli_util.h"
#include "tests/gpu_test_size.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

bool simulated() { return cuda::device_name().rfind("simulated", 0) == 0; }

TEST(GpuHwCounters, UnderTheSimulatorOneLineSaysWhy) {
  if (cuda::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  if (!simulated()) GTEST_SKIP() << "a real GPU: GpuHwCounters.ReadsPlausibleCounters";
  const cuda::HwProfiler profiler;
  EXPECT_NE(profiler.unavailable().find("GPGPU-Sim"), std::string::npos) << profiler.unavailable();
  const auto dir = test::temp_dir("gpu_hw_sim");
  const test::CommandResult r = test::run_raycoh(
      "table --scenes cornell --res 32x24 --frames 1 --generators noopt "
      "--encoders none --tracers cuda:counters=hw --out " +
      (dir / "t.csv").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("hardware counters not available (the device is GPGPU-Sim"), std::string::npos) << r.output;
  for (const auto& row : test::read_rows(dir / "t.csv")) {
    EXPECT_EQ(row.at("run_under"), "");  // an ordinary (simulated) timing
    for (const std::string& c : hw_column_names()) EXPECT_EQ(row.at(c), "") << c;
  }
}

void expect_plausible(const std::map<std::string, std::string>& row) {
  const std::string where = row.at("method") + " " + row.at("tracer_params");
  EXPECT_EQ(row.at("run_under"), kHwCountersRunUnder) << where;
  auto value = [&](const std::string& c) {
    EXPECT_FALSE(row.at(c).empty()) << where << ": " << c;
    return row.at(c).empty() ? -1.0 : std::stod(row.at(c));
  };
  for (const char* pct : {"hw_l1_hit_pct", "hw_l2_hit_pct", "hw_issue_pct", "hw_l1_util_pct", "hw_occupancy_pct"}) {
    EXPECT_GE(value(pct), 0.0) << where << ": " << pct;
    EXPECT_LE(value(pct), 100.0) << where << ": " << pct;
  }
  EXPECT_GT(value("hw_occupancy_pct"), 0.0) << where;
  EXPECT_GT(value("hw_inst_per_ray"), 10.0) << where;
  EXPECT_GT(value("hw_l1_wavefronts_per_ray"), 0.0) << where;
  EXPECT_GT(value("hw_l2_bytes_per_ray"), 0.0) << where;
  EXPECT_GE(value("hw_dram_bytes_per_ray"), 0.0) << where;
  EXPECT_GE(value("hw_pass_dram_bytes_per_ray"), value("hw_dram_bytes_per_ray")) << where;
}

TEST(GpuHwCounters, ReadsPlausibleCounters) {
  if (cuda::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  if (simulated()) GTEST_SKIP() << "GPGPU-Sim: GpuHwCounters.UnderTheSimulatorOneLineSaysWhy";
  {
    const cuda::HwProfiler probe;
    if (!probe.unavailable().empty()) GTEST_SKIP() << probe.unavailable();
  }
  const auto dir = test::temp_dir("gpu_hw_counters");
  const std::string res = test::gpu_test_size<std::string>("320x240", "32x24");
  const test::CommandResult r =
      test::run_raycoh("table --scenes cornell --res " + res +
                       " --frames 1 --generators noopt,ours --encoders none,twopoint "
                       "--tracers cuda:counters=hw,cuda:counters=hw,bvh=cwbvh,cuda:counters=hw,pipeline=host --out " +
                       (dir / "t.csv").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("MEASURED hardware counters of the trace kernels"), std::string::npos) << r.output;
  const auto rows = test::read_rows(dir / "t.csv");
  ASSERT_EQ(rows.size(), 3u * 5u);  // 3 tracers x (primary + 2 generators x 2 encoders)
  for (const auto& row : rows) expect_plausible(row);
}

}  // namespace
}  // namespace raycoh
