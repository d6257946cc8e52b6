// `raycoh table`: the paper's Table 1 layout (methods down, scenes across, one table per tracer).
#pragma once

#include <vector>

#include "harness/speed/experiment.h"
#include "records/speed_interval.h"

namespace raycoh {

struct TableOptions {
  ExperimentOptions experiment;  // its methods are made from generators x encoders
  // Empty generators and encoders (neither option given): the comparison, comparison_methods().
  std::vector<PluginSpec> generators;
  std::vector<PluginSpec> encoders;
  TableOptions() {
    experiment.scenes = {"cornell", "voxels"};
    experiment.tracers = {{"cpu", ""}, {"simt", ""}};
    experiment.width = 640;  // the default run: under a minute on 2 cores (README)
    experiment.height = 480;
    experiment.frames = 2;
    experiment.out = "raycoh-table.csv";
  }
};

// The default table's methods: noopt, ours and contiguous as generated, and noopt with every reordering encoder.
std::vector<Method> comparison_methods();
int run_table(const TableOptions& options, const Provenance& provenance);

// A tracer that read the GPU's own counters (cuda:counters=hw; harness/speed/table_hw.cpp): its measured hw columns per
// method (down) and scene (across), in place of speeds its replayed kernels do not have.
void print_hw_counters(const std::vector<SceneResult>& results, const std::vector<Method>& methods, const ResultKey& tl,
                       const std::string& name, const std::string& header);

// A shard's run (--shard I/N) prints no tables (they need every row): one line saying what was written. Returns 0.
int print_shard_done(const ExperimentOptions& e, const Provenance& provenance);

// "12.34 (1.05x)": a value and its ratio to the baseline; shared by the table and sweep printouts.
std::string ratio_cell(double value, double base);
// "12.34 (1.05x [1.01, 1.09])": a measured value and its ratio to noopt with the ratio's paired interval
// (records/speed_interval.h); `base`: noopt's own cell, "12.34 (1.00x)".
std::string ratio_cell(double value, const SpeedRatio& r, bool base = false);

}  // namespace raycoh
