// `cuda:counters=hw` without a GPU (tracers/hw_counters.h, records/hw_columns.h): the one line that says why the
// counters cannot be read, decided from injected conditions (no device, GPGPU-Sim, libcupti missing, profiling
// restricted to administrators, another CUPTI failure); the parameter; how profiled ranges become a trace's
// counters; the hw_* columns (empty without counters, per ray with them, round-tripped through the CSV); rows
// run_under cupti-counters summed as counters and left out as timings; validate and tune refusing the mode.
#include "tracers/hw_counters.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "harness/report/report_parts.h"
#include "plugins/tracer_registry.h"
#include "records/experiment_row.h"
#include "records/experiment_sums.h"
#include "records/hw_columns.h"
#include "records/result_csv.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

HwCounterConditions gpu_ready() {
  HwCounterConditions c;
  c.devices = 1;
  return c;
}

TEST(HwCounters, AvailableWhenNothingStandsInTheWay) { EXPECT_EQ(hw_counters_unavailable(gpu_ready()), ""); }

TEST(HwCounters, EachReasonIsOneLineNamingIt) {
  HwCounterConditions none;
  HwCounterConditions sim = gpu_ready();
  sim.simulated = true;
  HwCounterConditions lib = gpu_ready();
  lib.library_error = "dlopen libcupti.so.13: cannot open shared object file";
  HwCounterConditions admin = gpu_ready();
  admin.cupti_status = kCuptiInsufficientPrivileges;
  admin.cupti_call = "cuptiProfilerGetCounterAvailability";
  HwCounterConditions vgpu = admin;
  vgpu.cupti_status = kCuptiVirtualizedInsufficientPrivileges;
  HwCounterConditions other = gpu_ready();
  other.cupti_status = 27;
  other.cupti_call = "cuptiRangeProfilerEnable";
  other.cupti_message = "CUPTI_ERROR_NOT_SUPPORTED";
  const std::vector<std::pair<HwCounterConditions, std::string>> cases = {
      {none, "no CUDA device"},
      {sim, "GPGPU-Sim"},
      {lib, "libcupti.so.13"},
      {admin, "NVreg_RestrictProfilingToAdminUsers"},
      {vgpu, "INSUFFICIENT_PRIVILEGES"},
      {other, "cuptiRangeProfilerEnable failed: CUPTI error 27 (CUPTI_ERROR_NOT_SUPPORTED)"}};
  for (const auto& [c, expected] : cases) {
    const std::string line = hw_counters_unavailable(c);
    EXPECT_NE(line.find("counters=hw"), std::string::npos) << line;
    EXPECT_NE(line.find(expected), std::string::npos) << line;
    EXPECT_NE(line.find("hw_* columns stay empty"), std::string::npos) << line;
    EXPECT_EQ(line.find('\n'), std::string::npos) << line;
  }
}

TEST(HwCounters, TheFirstReasonWins) {
  HwCounterConditions c;  // no device, and also simulated and without the library: the device is named
  c.simulated = true;
  c.library_error = "missing";
  EXPECT_NE(hw_counters_unavailable(c).find("no CUDA device"), std::string::npos);
  c.devices = 1;
  EXPECT_NE(hw_counters_unavailable(c).find("GPGPU-Sim"), std::string::npos);
}

TEST(HwCounters, CudaTracerTakesCountersHw) {
  for (const TracerInfo& t : tracer_infos()) {
    if (t.name != "cuda") continue;  // CUDA builds only
    const ParamTable& table = t.table();
    const auto it = std::find_if(table.begin(), table.end(), [](const ParamSpec& p) { return p.name == "counters"; });
    ASSERT_NE(it, table.end());
    EXPECT_NE(std::find(it->choices.begin(), it->choices.end(), "hw"), it->choices.end());
    EXPECT_EQ(it->def, "off");
  }
}

TEST(HwCounters, SpeedCommandsRefuseTheMode) {
  EXPECT_EQ(hw_counters_refusal("--tracer", ""), "");
  EXPECT_EQ(hw_counters_refusal("--tracer", "counters=on,bvh=cwbvh"), "");
  EXPECT_NE(hw_counters_refusal("--tracer", "bvh=cwbvh,counters=hw").find("--tracer: counters=hw"), std::string::npos);
  EXPECT_NE(hw_counters_refusal("--tracer", "counters=hw").find("no speeds"), std::string::npos);
}

TEST(HwCounters, MetricTableIsConsistent) {
  const std::vector<HwMetric>& m = hw_metrics();
  ASSERT_GE(m.size(), 10u);
  const std::vector<std::string> names = hw_metric_names();
  for (const HwMetric& q : m) {
    EXPECT_EQ(std::string(q.column).rfind("hw_", 0), 0u) << q.column;
    const bool per_ray = std::string(q.column).find("_per_ray") != std::string::npos;
    EXPECT_EQ(per_ray, q.kind == HwMetric::Kind::PerRay) << q.column;
    for (const char* n : q.metrics) EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
  }
  EXPECT_EQ(hw_column_names().size(), m.size() + 1);
  EXPECT_EQ(hw_column_names().back(), "hw_pass_dram_bytes_per_ray");
}

// scripts/hw_counters_check.py (the comparison with Nsight Compute) names the same metrics for the same columns.
TEST(HwCounters, TheNsightComparisonNamesTheSameMetrics) {
  std::ifstream in(std::string(RAYCOH_SOURCE_DIR) + "/scripts/hw_counters_check.py");
  const std::string script((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_FALSE(script.empty());
  for (const HwMetric& m : hw_metrics()) {
    const size_t at = script.find(std::string("\"") + m.column + "\": ([");
    ASSERT_NE(at, std::string::npos) << m.column;
    const std::string entry = script.substr(at, script.find("),", at) - at);
    for (const char* name : m.metrics) EXPECT_NE(entry.find(name), std::string::npos) << m.column << ": " << name;
  }
}

TEST(HwCounters, TraceKernelsAreRecognised) {
  EXPECT_TRUE(is_trace_kernel("_ZN6raycoh4cuda12_GLOBAL__N_117persistent_kernelILb0ENS_7BvhViewEEEvT0_"));
  EXPECT_TRUE(is_trace_kernel("void (anonymous namespace)::simple_kernel<false, BvhView>(...)"));
  EXPECT_TRUE(is_trace_kernel("fused_group_kernel"));
  EXPECT_FALSE(is_trace_kernel("key_kernel"));
  EXPECT_FALSE(is_trace_kernel("DeviceRadixSortOnesweepKernel"));
}

// Two trace kernels and a sort kernel: sums add, percentages weigh by instructions, DRAM counts every kernel.
TEST(HwCounters, RangesCombineIntoTheTraceCounters) {
  std::vector<HwRange> ranges(3);
  for (const std::string& n : hw_metric_names()) ranges[0].values[n] = ranges[1].values[n] = ranges[2].values[n] = 1;
  ranges[0].kernel = "persistent_kernel";
  ranges[0].values["smsp__inst_executed.sum"] = 300;
  ranges[0].values["l1tex__t_sector_hit_rate.pct"] = 50;
  ranges[0].values["dram__bytes_read.sum"] = 1000;
  ranges[1].kernel = "persistent_kernel";
  ranges[1].values["smsp__inst_executed.sum"] = 100;
  ranges[1].values["l1tex__t_sector_hit_rate.pct"] = 90;
  ranges[1].values["dram__bytes_read.sum"] = 500;
  ranges[1].values["l1tex__t_requests_pipe_lsu_mem_local_op_st.sum"] = 4;
  ranges[2].kernel = "DeviceRadixSortOnesweepKernel";
  ranges[2].values["dram__bytes_read.sum"] = 7000;
  ranges[2].values["smsp__inst_executed.sum"] = 1e9;
  const HwCounters h = combine_ranges(ranges);
  EXPECT_EQ(h.kernels, 2);
  EXPECT_DOUBLE_EQ(h.pass_dram_bytes, 8500);
  const std::vector<std::string> cols = hw_column_names();
  auto value = [&](const std::string& col) {
    const size_t i = static_cast<size_t>(std::find(cols.begin(), cols.end(), col) - cols.begin());
    return h.values.at(i);
  };
  EXPECT_DOUBLE_EQ(*value("hw_inst_per_ray"), 400);
  EXPECT_DOUBLE_EQ(*value("hw_dram_bytes_per_ray"), 1500);
  EXPECT_DOUBLE_EQ(*value("hw_l1_hit_pct"), (50 * 300 + 90 * 100) / 400.0);
  EXPECT_DOUBLE_EQ(*value("hw_local_requests_per_ray"), 2 + 5);  // ld + st, both kernels
}

TEST(HwCounters, AMetricTheChipLacksLeavesItsQuantityEmpty) {
  HwRange r;
  r.kernel = "persistent_kernel";
  for (const std::string& n : hw_metric_names()) r.values[n] = 2;
  r.values.erase("l1tex__throughput.avg.pct_of_peak_sustained_active");
  r.values.erase("l1tex__t_requests_pipe_lsu_mem_local_op_ld.sum");  // one of a sum's two
  const HwCounters h = combine_ranges({r});
  const std::vector<std::string> cols = hw_column_names();
  for (size_t i = 0; i < hw_metrics().size(); ++i) {
    const bool lacking = cols[i] == "hw_l1_util_pct" || cols[i] == "hw_local_requests_per_ray";
    EXPECT_EQ(h.values[i].has_value(), !lacking) << cols[i];
  }
}

ExperimentRow counter_row(int frame, double inst) {
  ExperimentRow r;
  r.scene = "cornell";
  r.pass = "secondary";
  r.method = "noopt";
  r.tracer = "cuda";
  r.tracer_params = "counters=hw";
  r.frame = frame;
  r.rays = 1000;
  r.provenance.run_under = kHwCountersRunUnder;
  HwCounters h;
  h.kernels = 1;
  h.values.assign(hw_metrics().size(), std::nullopt);
  h.values[0] = 42.5;  // hw_l1_hit_pct
  for (size_t i = 0; i < hw_metrics().size(); ++i)
    if (std::string(hw_metrics()[i].column) == "hw_inst_per_ray") h.values[i] = inst;
  h.pass_dram_bytes = 64000;
  set_hw_counters(r, h);
  return r;
}

TEST(HwCounters, ColumnsArePerRayAndEmptyWithoutCounters) {
  const ExperimentRow r = counter_row(0, 250000);
  const std::vector<std::string> cols = hw_column_names();
  ASSERT_EQ(r.hw.size(), cols.size());
  EXPECT_DOUBLE_EQ(*r.hw[0], 42.5);
  EXPECT_DOUBLE_EQ(*r.hw.back(), 64);
  for (size_t i = 0; i < cols.size(); ++i)
    if (cols[i] == "hw_inst_per_ray") {
      EXPECT_DOUBLE_EQ(*r.hw[i], 250);
    }
  ExperimentRow none = r;
  set_hw_counters(none, HwCounters{});  // no kernel read: every column empty
  for (const auto& v : none.hw) EXPECT_FALSE(v.has_value());
}

TEST(HwCounters, ColumnsRoundTripThroughTheCsv) {
  const Schema<ExperimentRow>& schema = experiment_schema();
  const std::vector<std::string> names = column_names(schema);
  for (const std::string& c : hw_column_names()) EXPECT_NE(std::find(names.begin(), names.end(), c), names.end()) << c;
  const ExperimentRow r = counter_row(0, 250000);
  std::vector<std::string> fields;
  for (const auto& c : schema) fields.push_back(c.write(r));
  const ExperimentRow back = read_row(schema, fields);
  ASSERT_EQ(back.hw.size(), r.hw.size());
  for (size_t i = 0; i < r.hw.size(); ++i) EXPECT_EQ(back.hw[i], r.hw[i]) << i;
  EXPECT_EQ(back.provenance.run_under, kHwCountersRunUnder);
  ExperimentRow plain;  // a timing row: its hw columns are empty text
  for (size_t i = 0; i < schema.size(); ++i)
    if (schema[i].name.rfind("hw_", 0) == 0) {
      EXPECT_EQ(schema[i].write(plain), "") << schema[i].name;
    }
}

TEST(HwCounters, RowsSumAsCountersNotTimes) {
  SceneResult res;
  accumulate(counter_row(0, 200000), 2, res);
  accumulate(counter_row(1, 400000), 2, res);
  ASSERT_EQ(res.tracers.size(), 1u);
  const Accumulated& a = res.by_tracer.at(res.tracers.front()).at("noopt");
  EXPECT_TRUE(a.hw.replayed);
  const std::vector<std::string> cols = hw_column_names();
  for (size_t i = 0; i < cols.size(); ++i)
    if (cols[i] == "hw_inst_per_ray") {
      EXPECT_DOUBLE_EQ(*a.hw.value(i), 300);
    }
  EXPECT_FALSE(a.hw.value(1).has_value());  // hw_l2_hit_pct was not read
}

// A CSV of counter rows: read_experiment leaves them out as timings, the report's counter section shows them.
TEST(HwCounters, ReportShowsCountersAndNoSpeeds) {
  const auto dir = test::temp_dir("hw_counters_report");
  const std::string path = (dir / "hw.csv").string();
  const Schema<ExperimentRow>& schema = experiment_schema();
  std::string text;
  for (const auto& c : schema) text += (text.empty() ? "" : ",") + c.name;
  for (int f = 0; f < 2; ++f) {
    text += "\n";
    const ExperimentRow r = counter_row(f, 300000);
    for (size_t i = 0; i < schema.size(); ++i) text += (i ? "," : "") + schema[i].write(r);
  }
  test::write_file(path, text + "\n");
  const ResultCsv c = read_result_csv(path);
  const Experiment e = read_experiment(c);
  EXPECT_EQ(e.not_timings, 2u);
  EXPECT_TRUE(e.tracers.empty());
  report_detail::Page p;
  report_detail::add_table(p, c);
  EXPECT_NE(p.md.find("Hardware counters, MEASURED"), std::string::npos) << p.md;
  EXPECT_NE(p.md.find("| cornell | noopt | 42.5 |"), std::string::npos) << p.md;
  EXPECT_NE(p.md.find("cupti-counters left out"), std::string::npos) << p.md;
}

}  // namespace
}  // namespace raycoh
