// `raycoh table`: per scene, frame, generator and tracer, trace primary and secondary rays, print a Markdown
// table in the layout of the paper's Table 1 (MRay/s and ratio to NoOpt) and write one CSV row per
// measurement (schema in results/README.md).
#pragma once

#include <string>
#include <vector>

#include "core/params.h"
#include "harness/provenance.h"

namespace raycoh {

struct TableOptions {
  std::vector<std::string> scenes{"cornell", "voxels"};
  std::vector<PluginSpec> generators{{"noopt", ""}};
  std::vector<PluginSpec> tracers{{"cpu", ""}, {"embree", ""}};
  int width = 320, height = 240;
  int frames = 4;
  uint32_t seed = 1;
  int repeats = 3;  // timed traces per measurement; the median is reported
  std::string out = "raycoh-table.csv";
};

// Returns the process exit code. Throws raycoh::Error on bad input (rows measured so far stay on disk).
int run_table(const TableOptions& options, const Provenance& provenance);

// Column names of the table CSV (without the provenance columns, which follow).
std::vector<std::string> table_columns();

}  // namespace raycoh
