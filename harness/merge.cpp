// `raycoh merge`: its options, and what the merge (records/merge.h) needs of the commands whose files it joins —
// their defaults for options a recorded command line does not give.
#include <CLI/CLI.hpp>
#include <memory>

#include "harness/common/cli.h"
#include "harness/common/command.h"
#include "harness/image/converge.h"
#include "harness/image/quality.h"
#include "harness/merge_defaults.h"
#include "harness/speed/experiment.h"
#include "harness/tune/tune_run.h"

namespace raycoh {

namespace {

// The scenes and methods of a quality or converge command line, with the command's defaults.
RunUnits command_units(bool quality, const std::vector<std::string>& words) {
  RunUnits u;
  std::vector<PluginSpec> generators;
  if (quality && !words.empty() && words.front() == "tune") {  // a sharded tune's error stage (harness/tune/tune.h)
    u.scenes = {option_value(words, "--scene", "")};
    u.methods = tune_quality_methods(option_value(words, "--space", TuneOptions{}.space),
                                     option_value(words, "--generator", TuneOptions{}.generator));
    return u;
  }
  if (quality) {
    u.scenes = split_scenes("--scenes", option_value(words, "--scenes", join(QualityOptions{}.scenes, ",")));
    generators =
        split_nonempty("--generators", option_value(words, "--generators", join_specs(QualityOptions{}.generators)));
  } else {
    u.scenes = {option_value(words, "--scene", ConvergeOptions{}.scene)};
    generators =
        split_nonempty("--generators", option_value(words, "--generators", join_specs(ConvergeOptions{}.generators)));
  }
  for (const PluginSpec& g : generators) u.methods.push_back(g.text());
  return u;
}

}  // namespace

MergeCommands merge_command_defaults() {
  return {ExperimentOptions{}.frames, TuneOptions{}.speed.frames, command_units};
}

BoundCommand bind_merge(CLI::App& parent) {
  auto o = std::make_shared<MergeOptions>();
  o->commands = merge_command_defaults();
  CLI::App* cmd = parent.add_subcommand(
      "merge",
      "join the CSV files of a sharded table, sweep, quality or converge (--shard I/N) into what one process writes");
  cmd->add_option("--out", o->out, "merged CSV file to write")->required();
  cmd->add_option("inputs", o->inputs, "the shards' CSV files (each shard's finished --out)")->required();
  cmd->add_flag("--force", o->force, "replace an existing --out");
  return {cmd, [o](const Provenance& provenance) { return run_merge(*o, provenance); }};
}

}  // namespace raycoh
