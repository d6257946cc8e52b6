#include "harness/repeat_timing.h"

#include <algorithm>

#include "records/speed_interval.h"

namespace raycoh {

double Timing::median() const { return median_interval(samples_s).median; }

double Timing::min() const { return samples_s.empty() ? 0.0 : *std::min_element(samples_s.begin(), samples_s.end()); }

void set_host_times(ExperimentRow& row, const Timing& t, double overhead_ms) {
  const double rays = static_cast<double>(row.rays);
  const double median_s = t.median();
  row.trace_ms = median_s * 1e3;
  row.trace_ms_min = t.min() * 1e3;
  row.mray_s = median_s > 0 ? rays / median_s * 1e-6 : 0.0;
  row.e2e_ms = overhead_ms + row.trace_ms;
  row.e2e_mray_s = row.e2e_ms > 0 ? rays / row.e2e_ms * 1e-3 : 0.0;
  row.trace_samples_ms.clear();
  row.e2e_samples_ms.clear();
  if (t.samples_s.size() < 2) return;
  for (double s : t.samples_s) {
    row.trace_samples_ms.push_back(s * 1e3);
    row.e2e_samples_ms.push_back(overhead_ms + s * 1e3);
  }
  set_intervals(row);
}

void set_intervals(ExperimentRow& row) {
  if (row.trace_samples_ms.size() < 2) return;
  const MedianInterval trace = median_interval(row.trace_samples_ms);
  row.trace_ms_lo = trace.lo;
  row.trace_ms_hi = trace.hi;
  row.interval_level = trace.level;
  if (row.e2e_samples_ms.size() < 2) return;
  const MedianInterval e2e = median_interval(row.e2e_samples_ms);
  row.e2e_ms_lo = e2e.lo;
  row.e2e_ms_hi = e2e.hi;
}

}  // namespace raycoh
