// The experiment CSV's hardware-counter columns (hw_*, results/README.md): the GPU's own counters of a row's trace
// kernels, measured by `cuda:counters=hw` (tracers/hw_counters.h), beside the `simt` model's modeled columns and
// never added to them. Empty on every other row, and where the counters could not be read.
#pragma once

#include <string>
#include <vector>

#include "records/experiment_row.h"
#include "records/schema.h"
#include "tracers/hw_counters.h"

namespace raycoh {

// The column names, in file order: one per hw_metrics() entry, then hw_pass_dram_bytes_per_ray.
std::vector<std::string> hw_column_names();
// Appends those columns to the experiment schema (ExperimentRow::hw holds their values in that order).
void append_hw_columns(Schema<ExperimentRow>& s);
// The row's hw columns from a trace's counters: per-ray quantities divided by row.rays (which must be set),
// percentages as they are; a quantity the chip did not know stays empty.
void set_hw_counters(ExperimentRow& row, const HwCounters& c);

}  // namespace raycoh
