// The options `table` and `sweep` share: --tracers, --res, --frames, --seed, --repeat, --out, --force, --shard, their
// defaults taken from the ExperimentOptions bound. Text only; run_experiment checks every range.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "harness/speed/experiment.h"

namespace raycoh {

struct ExperimentText {
  std::string tracers, res, shard;
};
void bind_experiment(CLI::App* cmd, ExperimentOptions& o, ExperimentText& text);
void resolve_experiment(ExperimentOptions& o, const ExperimentText& text);

}  // namespace raycoh
