// The experiment CSVs (table, sweep) read back for the report and tune: every row read into an ExperimentRow and
// summed by the aggregator the console tables fill live (records/experiment_row.h: SceneResult, Accumulated, keyed
// by records/result_key.h), with the run's provenance (records/result_csv.h reads the files).
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include "records/experiment_row.h"
#include "records/result_csv.h"

namespace raycoh {

// What a method is, the same in each of its rows: its generator, its encoder ("none" without one), and the typed
// layout of its batch (tile, K, order).
struct MethodColumns {
  std::string generator, encoder;
  RecordedColumns recorded;
};

struct Experiment {
  std::vector<std::string> scenes, methods;        // in file order
  std::vector<ResultKey> tracers;                  // in file order
  std::map<std::string, SceneResult> results;      // scene -> its sums
  std::map<std::string, MethodColumns> method_of;  // method label -> what it is
  std::set<std::string> revisions, resolutions, frames, cpus, commands;
  // Rows run under a profiler or sanitizer (the run_under column): not timings, so left out of every sum above.
  size_t not_timings = 0;
  std::set<std::string> run_under;
  // Of those, the rows whose kernels CUPTI replayed for their hardware counters (`cuda:counters=hw`), summed apart
  // by the same aggregator (only their Accumulated::hw is read): scene -> sums, scenes and methods in file order.
  std::map<std::string, SceneResult> hw_results;
  std::vector<std::string> hw_scenes, hw_methods;

  // A scene's sums of one tracer: method label -> sums.
  const std::map<std::string, Accumulated>& sums(const std::string& scene, const ResultKey& tracer) const {
    return results.at(scene).by_tracer.at(tracer);
  }
  // Whether the tracer's figures are a GPU model's (modeled, never measured).
  bool modeled(const ResultKey& tracer) const;
  // The tracer's name in headings and figures (records/result_key.h heading_labels).
  std::string label(const ResultKey& tracer) const { return heading_labels(tracers).at(tracer); }
};

// A row of a table or sweep CSV as the record it was written from. Columns the file lacks (an older file) keep
// their defaults, the typed recorded columns are read through the plugins' tables (recorded_of), and a value its
// column cannot hold is left at its default, as the report always read one.
ExperimentRow experiment_row_of(const ResultCsv& c, const std::vector<std::string>& row);

Experiment read_experiment(const ResultCsv& c);

}  // namespace raycoh
