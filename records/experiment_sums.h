// The experiment CSVs (table, sweep) read back for figures: per scene, tracer label and method, the sums over
// frames of rays and of measured and modeled times, with the run's provenance (records/result_csv.h reads them).
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include "records/result_csv.h"
#include "records/speed_interval.h"

namespace raycoh {

struct Sums {
  double rays = 0, trace_ms = 0, e2e_ms = 0, modeled_ms = 0, modeled_e2e_ms = 0;
  double gpu_e2e_ms = 0;  // device pipelines (cuda): the pass's measured span on the device, 0 elsewhere
  std::string generator, encoder;
  // Every repeat by frame, for the ratio intervals (records/speed_interval.h): the trace, and end to end (device
  // pipelines: the measured span). Rows written before repeats were kept give their median alone.
  FrameSeries trace_times, e2e_times;
  RecordedColumns recorded;  // of the method's rows (the same in each)
  double speed(bool modeled, bool e2e) const {
    const double ms = modeled ? (e2e ? modeled_e2e_ms : modeled_ms) : (e2e ? e2e_ms : trace_ms);
    return ms > 0 ? rays / ms * 1e-3 : 0.0;
  }
};

struct Experiment {
  std::vector<std::string> scenes, tracers, methods;  // in file order
  std::map<std::string, bool> modeled;                // tracer label -> figures are the GPU model's
  std::map<std::string, std::map<std::string, std::map<std::string, Sums>>> sums;  // scene, tracer, method
  std::set<std::string> revisions, resolutions, frames, cpus, commands;
  // Rows run under a profiler or sanitizer (the run_under column): not timings, so left out of every sum above.
  size_t not_timings = 0;
  std::set<std::string> run_under;
};

Experiment read_experiment(const ResultCsv& c);

}  // namespace raycoh
