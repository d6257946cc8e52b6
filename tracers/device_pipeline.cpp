#include "tracers/device_pipeline.h"

#include <algorithm>

#include "core/error.h"

namespace raycoh {

namespace {

double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

DeviceStageTimes median_stage_times(std::vector<DeviceStageTimes> passes, double* trace_min_ms) {
  RAYCOH_CHECK(!passes.empty(), "median_stage_times of no passes");
  auto median = [&](double DeviceStageTimes::*field) {
    std::vector<double> v;
    for (const DeviceStageTimes& p : passes) v.push_back(p.*field);
    return median_of(std::move(v));
  };
  DeviceStageTimes m;
  m.gen_ms = median(&DeviceStageTimes::gen_ms);
  m.key_ms = median(&DeviceStageTimes::key_ms);
  m.sort_ms = median(&DeviceStageTimes::sort_ms);
  m.permute_ms = median(&DeviceStageTimes::permute_ms);
  m.trace_ms = median(&DeviceStageTimes::trace_ms);
  m.span_ms = median(&DeviceStageTimes::span_ms);
  m.fused = passes.front().fused;
  if (trace_min_ms) {
    *trace_min_ms = passes.front().trace_ms;
    for (const DeviceStageTimes& p : passes) *trace_min_ms = std::min(*trace_min_ms, p.trace_ms);
  }
  return m;
}

}  // namespace raycoh
