// The host side of the device pipeline (tracers/device_pipeline.h, harness/speed/device_rows.h) and of the modeled
// stages beside it (simt/pipeline_model.h modeled_stages): medians, the measured columns a device row gets, what
// the console sums, and which modeled stages a reordering has. No GPU needed: the passes here are stand-ins that
// return given stage times.
#include "harness/speed/device_rows.h"

#include <gtest/gtest.h>

#include <vector>

#include "harness/speed/repeat_timing.h"
#include "records/experiment_row.h"
#include "simt/gpu_model.h"
#include "simt/pipeline_model.h"
#include "simt/stage_model.h"
#include "tracers/device_pipeline.h"

namespace raycoh {
namespace {

DeviceStageTimes stages(double gen, double key, double sort, double permute, double trace, double span) {
  DeviceStageTimes t;
  t.gen_ms = gen;
  t.key_ms = key;
  t.sort_ms = sort;
  t.permute_ms = permute;
  t.trace_ms = trace;
  t.span_ms = span;
  return t;
}

std::string column(const ExperimentRow& row, const std::string& name) {
  const std::vector<std::string> names = column_names(experiment_schema());
  const std::vector<std::string> text = write_row(experiment_schema(), row);
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return text[i];
  ADD_FAILURE() << "no column " << name;
  return "";
}

TEST(DeviceRows, MedianOfEachStageOnItsOwnAndTheFastestTrace) {
  double trace_min = 0;
  const DeviceStageTimes m =
      median_stage_times({stages(1, 9, 5, 0, 7, 30), stages(3, 1, 4, 0, 2, 10), stages(2, 5, 6, 0, 9, 20)}, &trace_min);
  EXPECT_EQ(m.gen_ms, 2);
  EXPECT_EQ(m.key_ms, 5);
  EXPECT_EQ(m.sort_ms, 5);
  EXPECT_EQ(m.permute_ms, 0);
  EXPECT_EQ(m.trace_ms, 7);
  EXPECT_EQ(m.span_ms, 20);
  EXPECT_EQ(trace_min, 2);
  EXPECT_EQ(m.stages_ms(), 2 + 5 + 5 + 0 + 7);
}

TEST(DeviceRows, TimingRunsWarmUpOnceAndCountingRunsPassOnce) {
  int calls = 0;
  auto pass = [&] {
    ++calls;  // the first (warm-up) pass is slow and must not be measured
    return calls == 1 ? stages(100, 100, 100, 100, 100, 500) : stages(1, 1, 1, 1, calls, 6);
  };
  const DeviceMeasurement timed = measure_device(pass, 3, false);
  EXPECT_EQ(calls, 4);
  EXPECT_EQ(timed.median.gen_ms, 1);
  EXPECT_EQ(timed.median.trace_ms, 3);  // traces 2, 3, 4
  EXPECT_EQ(timed.trace_min_ms, 2);
  calls = 0;
  const DeviceMeasurement counted = measure_device(pass, 3, true);
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(counted.median.trace_ms, 100);
}

TEST(DeviceRows, DeviceRowsHoldMeasuredGpuStagesAndTheSpan) {
  ExperimentRow row;
  EXPECT_EQ(column(row, "pipeline"), "host");  // every row made on the host says so
  EXPECT_EQ(column(row, "gpu_e2e_ms"), "");
  row.rays = 2000;
  DeviceMeasurement m;
  m.median = stages(0.5, 0.25, 0.125, 0.0625, 1.0, 2.5);
  m.trace_min_ms = 0.75;
  set_device_times(row, m, false);
  EXPECT_EQ(column(row, "pipeline"), "device");
  EXPECT_EQ(column(row, "gen_ms"), "0.5000");
  EXPECT_EQ(column(row, "key_ms"), "0.2500");
  EXPECT_EQ(column(row, "sort_ms"), "0.1250");
  EXPECT_EQ(column(row, "permute_ms"), "0.0625");
  EXPECT_EQ(column(row, "trace_ms"), "1.0000");
  EXPECT_EQ(column(row, "trace_ms_min"), "0.7500");
  EXPECT_EQ(column(row, "mray_s"), "2.000");
  EXPECT_EQ(column(row, "e2e_ms"), "1.9375");   // the stages' sum
  EXPECT_EQ(column(row, "gpu_e2e_ms"), "2.5");  // the measured span, not the sum
  EXPECT_EQ(column(row, "gpu_e2e_mray_s"), "0.8");
  EXPECT_EQ(column(row, "modeled_e2e_ms"), "");  // nothing modeled on a measured row
  const ExperimentRow back = read_row(experiment_schema(), write_row(experiment_schema(), row));
  EXPECT_EQ(back.pipeline, "device");
  EXPECT_EQ(back.gpu_e2e_ms, 2.5);

  ExperimentRow counting;
  counting.rays = 2000;
  set_device_times(counting, m, true);
  EXPECT_EQ(column(counting, "pipeline"), "device");
  EXPECT_EQ(column(counting, "gpu_e2e_ms"), "");  // the counting kernel is no traversal time
}

// A host pipeline times generation and reordering once per repeat: each repeat's end to end is its own stages plus
// its own trace, so the end-to-end interval holds the stages' spread too; each stage's time is its median.
TEST(HostRows, EachRepeatsEndToEndHoldsItsOwnStages) {
  Timing trace;
  trace.samples_s = {0.003, 0.001, 0.002};
  StageSamples st;
  st.gen_ms = {10, 40, 20};
  st.key_ms = {1, 1, 4};
  st.sort_ms = {2, 2, 2};
  ExperimentRow row;
  row.rays = 1000;
  set_host_times(row, trace, st);
  EXPECT_EQ(row.e2e_samples_ms, (std::vector<double>{16, 44, 28}));  // 10+1+2+3, 40+1+2+1, 20+4+2+2
  EXPECT_DOUBLE_EQ(row.gen_ms, 20);
  EXPECT_DOUBLE_EQ(row.key_ms, 1);
  EXPECT_DOUBLE_EQ(row.permute_ms, 0);  // indirect: no gather ran
  EXPECT_DOUBLE_EQ(row.e2e_ms, 28);     // the median of the sums, not the sum of the medians (25)
  EXPECT_EQ(*row.e2e_ms_lo, 16);
  EXPECT_EQ(*row.e2e_ms_hi, 44);
  EXPECT_EQ(row.gen_samples_ms, st.gen_ms);
  EXPECT_TRUE(row.permute_samples_ms.empty());
  // One repeat (a model): no samples, the end to end the sum of the stages and the trace.
  Timing once;
  once.samples_s = {0.005};
  ExperimentRow one;
  one.rays = 1000;
  set_host_times(one, once, StageSamples{{7}, {}, {}, {}});
  EXPECT_DOUBLE_EQ(one.e2e_ms, 12);
  EXPECT_TRUE(one.e2e_samples_ms.empty());
  EXPECT_TRUE(one.gen_samples_ms.empty());
}

// Timed passes give every stage's repeats (a stage that did not run: none), the trace's and the span's, and the
// median intervals of trace and span.
TEST(DeviceRows, TimedPassesKeepEveryStagesRepeatsAndTheIntervals) {
  auto pass = [n = 0]() mutable {
    ++n;
    return stages(0.1 * n, 0, 0.3, 0, 1.0 + n, 2.0 + n);  // no keys: key and gather did not run
  };
  const DeviceMeasurement m = measure_device(pass, 7, false);  // the first (warm-up) pass is not kept
  ExperimentRow row;
  row.rays = 1000;
  set_device_times(row, m, false);
  EXPECT_EQ(row.trace_samples_ms, (std::vector<double>{3, 4, 5, 6, 7, 8, 9}));
  EXPECT_EQ(row.e2e_samples_ms, (std::vector<double>{4, 5, 6, 7, 8, 9, 10}));
  EXPECT_EQ(row.gen_samples_ms.size(), 7u);
  EXPECT_EQ(row.sort_samples_ms, std::vector<double>(7, 0.3));
  EXPECT_TRUE(row.key_samples_ms.empty());
  EXPECT_TRUE(row.permute_samples_ms.empty());
  EXPECT_EQ(*row.trace_ms_lo, 3);  // 7 repeats: [min, max] at 1 - 2/128
  EXPECT_EQ(*row.trace_ms_hi, 9);
  EXPECT_EQ(*row.e2e_ms_hi, 10);
  EXPECT_NEAR(*row.interval_level, 1.0 - 2.0 / 128, 1e-12);
  EXPECT_EQ(column(row, "key_samples_ms"), "");
  EXPECT_EQ(column(row, "sort_samples_ms"), "0.3;0.3;0.3;0.3;0.3;0.3;0.3");
}

TEST(DeviceRows, TheConsoleSumsTheSpanOfDeviceRowsOnly) {
  SceneResult res;
  ExperimentRow row;
  row.pass = "secondary";
  row.method = "noopt";
  row.rays = 1000;
  DeviceMeasurement m;
  m.median = stages(1, 0, 0, 0, 2, 4);
  set_device_times(row, m, false);
  row.tracer = "cuda";
  accumulate(row, 2, res);
  accumulate(row, 2, res);
  const Accumulated& a = res.by_tracer.at(result_key(row)).at("noopt");
  EXPECT_TRUE(a.measured.on_device);
  EXPECT_DOUBLE_EQ(a.measured.gpu_span_s, 8e-3);
  EXPECT_DOUBLE_EQ(a.measured.e2e_s, 6e-3);
  EXPECT_DOUBLE_EQ(a.gpu_span_mray_s(), 2000 / 8e-3 * 1e-6);
  ExperimentRow host;
  host.pass = "secondary";
  host.method = "noopt";
  host.rays = 1000;
  host.modeled_ms = 1.0;
  host.modeled_e2e_ms = 3.0;
  host.modeled_gen_ms = 0.5;
  host.modeled_key_ms = 0.25;
  host.modeled_sort_ms = 0.75;
  host.modeled_permute_ms = 0.5;
  host.tracer = "simt";
  accumulate(host, 1, res);
  const Accumulated& s = res.by_tracer.at(result_key(host)).at("noopt");
  EXPECT_FALSE(s.measured.on_device);
  EXPECT_DOUBLE_EQ(s.model.gen_s, 0.5e-3);
  EXPECT_DOUBLE_EQ(s.model.reorder_s, 1.5e-3);
}

TEST(ModeledStages, EachReorderingModelsItsOwnStages) {
  const GpuModelConfig gpu = gpu_preset("rtx3060");
  std::vector<uint32_t> order(4096);
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<uint32_t>((i * 1031) % order.size());
  StageWork w;
  w.width = 128;
  w.height = 64;
  w.rays = order.size();
  const ModeledStages none = stage_model(gpu, w, {});
  EXPECT_EQ(none.gen_ms, stage_generation_ms(gpu, w));
  EXPECT_EQ(none.reorder_ms(), 0.0);
  w.key = KeyKind::Origin;
  w.key_bits = 32;
  const ModeledStages physical = stage_model(gpu, w, order);
  EXPECT_EQ(physical.key_ms, stage_key_ms(gpu, w));
  EXPECT_EQ(physical.sort_ms, stage_sort_ms(gpu, w.rays, 32));
  EXPECT_EQ(physical.permute_ms, stage_permute_ms(gpu, permute_bytes(order.data(), order.size()), w.rays));
  EXPECT_GT(physical.permute_ms, 0.0);
  w.physical = false;
  const ModeledStages indirect = stage_model(gpu, w, order);
  EXPECT_EQ(indirect.permute_ms, 0.0);
  EXPECT_EQ(indirect.sort_ms, physical.sort_ms);
  w.physical = true;
  w.window = 256;
  const ModeledStages window = stage_model(gpu, w, order);
  EXPECT_EQ(window.key_ms, 0.0);
  EXPECT_EQ(window.permute_ms, 0.0);
  EXPECT_EQ(window.sort_ms, stage_kernel_ms(gpu, window_bytes(w.rays, true), 0, 0));
}

}  // namespace
}  // namespace raycoh
