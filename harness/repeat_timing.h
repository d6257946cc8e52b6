// The repeated timing of one measurement and what a row records of it: the median, the fastest, the median's
// interval and every repeat (records/speed_interval.h), for tracers timed on the host's clock or by their own
// device clock. Device pipelines record theirs in harness/device_rows.h.
#pragma once

#include <vector>

#include "records/experiment_row.h"

namespace raycoh {

// Every timed repeat of one measurement, in seconds, in the order they ran.
struct Timing {
  std::vector<double> samples_s;
  double median() const;
  double min() const;
};

// Times `repeats` calls of fn (fn returns its own time in seconds).
template <class Fn>
Timing time_repeats(Fn&& fn, int repeats) {
  Timing t;
  for (int r = 0; r < repeats; ++r) t.samples_s.push_back(fn());
  return t;
}

// A row's trace times from `t` (trace_ms, trace_ms_min, mray_s, the trace interval and samples) and its end to end:
// `overhead_ms` (generation + key + sort + permute, timed once before the repeats) + each repeat's trace. row.rays
// must be set. One repeat: no interval columns.
void set_host_times(ExperimentRow& row, const Timing& t, double overhead_ms);

// The interval columns of a row from its samples (trace_samples_ms, e2e_samples_ms): absent below two repeats.
void set_intervals(ExperimentRow& row);

}  // namespace raycoh
