#include "harness/speed/device_rows.h"

#include <vector>

#include "harness/speed/repeat_timing.h"
#include "simt/pipeline_model.h"

namespace raycoh {

namespace {

double mray_s(size_t rays, double ms) { return ms > 0 ? static_cast<double>(rays) / ms * 1e-3 : 0.0; }

// Every pass's time of each stage that ran (its median above 0: a fused pass has no generation of its own, a pass
// without keys no key, sort or gather).
void set_stage_samples(ExperimentRow& row, const DeviceMeasurement& m) {
  const std::pair<double DeviceStageTimes::*, std::vector<double> ExperimentRow::*> stages[] = {
      {&DeviceStageTimes::gen_ms, &ExperimentRow::gen_samples_ms},
      {&DeviceStageTimes::key_ms, &ExperimentRow::key_samples_ms},
      {&DeviceStageTimes::sort_ms, &ExperimentRow::sort_samples_ms},
      {&DeviceStageTimes::permute_ms, &ExperimentRow::permute_samples_ms}};
  for (const auto& [time, samples] : stages) {
    (row.*samples).clear();
    if (m.median.*time <= 0) continue;
    for (const DeviceStageTimes& p : m.passes) (row.*samples).push_back(p.*time);
  }
}

}  // namespace

DeviceMeasurement measure_device(const std::function<DeviceStageTimes()>& pass, int repeats, bool counting) {
  std::vector<DeviceStageTimes> passes;
  if (counting) {
    passes.push_back(pass());
  } else {
    pass();  // warm-up
    for (int r = 0; r < repeats; ++r) passes.push_back(pass());
  }
  DeviceMeasurement m;
  m.passes = passes;
  m.median = median_stage_times(std::move(passes), &m.trace_min_ms);
  return m;
}

void set_device_times(ExperimentRow& row, const DeviceMeasurement& m, bool counting) {
  const DeviceStageTimes& t = m.median;
  row.pipeline = t.fused ? "fused" : "device";
  row.gen_ms = t.gen_ms;
  row.key_ms = t.key_ms;
  row.sort_ms = t.sort_ms;
  row.permute_ms = t.permute_ms;
  row.trace_ms = t.trace_ms;
  row.trace_ms_min = m.trace_min_ms;
  row.mray_s = mray_s(row.rays, t.trace_ms);
  row.e2e_ms = t.stages_ms();
  row.e2e_mray_s = mray_s(row.rays, row.e2e_ms);
  if (counting) return;  // the counting kernel's time is no traversal time: no end-to-end span
  row.gpu_e2e_ms = t.span_ms;
  row.gpu_e2e_mray_s = mray_s(row.rays, t.span_ms);
  row.trace_samples_ms.clear();
  row.e2e_samples_ms.clear();
  if (m.passes.size() < 2) return;
  for (const DeviceStageTimes& p : m.passes) {
    row.trace_samples_ms.push_back(p.trace_ms);
    row.e2e_samples_ms.push_back(p.span_ms);
  }
  set_stage_samples(row, m);
  set_intervals(row);
}

void set_stage_traffic(ExperimentRow& row, const DevicePipeline& pipeline, const Encoder& encoder, PermuteMode mode,
                       size_t pixels, bool fused) {
  const bool physical = mode == PermuteMode::Physical;
  std::vector<uint32_t> order;
  if (!fused && encoder.key_bits() > 0 && physical) {
    RayBatch generated, permuted;
    std::vector<Hit> hits;
    pipeline.download_secondary(generated, order, permuted, hits);
  }
  const ModeledStages s = stage_traffic(pixels, encoder.key_bits(), encoder.window(), physical, row.rays, order, fused);
  row.modeled_gen_bytes = s.gen_bytes;
  if (encoder.key_bits() > 0 && !fused) {
    row.modeled_key_bytes = s.key_bytes;
    row.modeled_sort_bytes = s.sort_bytes;
    if (physical) row.modeled_permute_bytes = s.permute_bytes;
  }
}

}  // namespace raycoh
