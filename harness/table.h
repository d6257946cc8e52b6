// `raycoh table` (the paper's Table 1 layout) and `raycoh sweep` (its Table 3 layout: tile size x group size).
#pragma once

#include <string>
#include <vector>

#include "harness/experiment.h"

namespace raycoh {

struct TableOptions {
  std::vector<std::string> scenes{"cornell", "voxels"};
  std::vector<PluginSpec> generators{{"noopt", ""}};
  std::vector<PluginSpec> encoders{{"none", ""}};
  std::vector<PluginSpec> tracers{{"cpu", ""}, {"embree", ""}};
  int width = 320, height = 240;
  int frames = 4;
  uint32_t seed = 1;
  int repeats = 3;  // timed traces per measurement; the median is reported
  std::string permute = "physical";
  std::string out = "raycoh-table.csv";
};
int run_table(const TableOptions& options, const Provenance& provenance);

struct SweepOptions {
  std::string scene;
  std::string generator = "ours";  // or "tile"
  std::vector<std::pair<int, int>> tiles{{8, 8}, {16, 8}, {16, 16}, {32, 8}};
  std::vector<int> groups{8, 16, 32, 64};
  std::vector<PluginSpec> tracers{{"cpu", ""}};
  int width = 320, height = 240;
  int frames = 4;
  uint32_t seed = 1;
  int repeats = 3;
  std::string out = "raycoh-sweep.csv";
};
int run_sweep(const SweepOptions& options, const Provenance& provenance);

}  // namespace raycoh
