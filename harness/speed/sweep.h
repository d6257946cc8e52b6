// `raycoh sweep`: the paper's Table 3 layout, tile size W x H down, group size K across, for `ours` (or `tile`).
#pragma once

#include <utility>
#include <vector>

#include "harness/speed/experiment.h"

namespace raycoh {

struct SweepOptions {
  ExperimentOptions experiment;    // one scene; its methods are noopt and one per (tile, K) cell
  std::string generator = "ours";  // ours or tile
  std::vector<std::pair<int, int>> tiles{{8, 8}, {16, 8}, {16, 16}, {32, 8}};  // each in [1, 1024]
  std::vector<int> groups{8, 16, 32, 64};  // each in the generator's range of k (ours_params())
  SweepOptions() { experiment.out = "raycoh-sweep.csv"; }
};
int run_sweep(const SweepOptions& options, const Provenance& provenance);

}  // namespace raycoh
