#include "harness/speed/experiment_cli.h"

#include <fmt/format.h>

#include <string>
#include <tuple>

#include "harness/common/cli.h"
#include "records/shard.h"

namespace raycoh {

void bind_experiment(CLI::App* cmd, ExperimentOptions& o, ExperimentText& t) {
  t.tracers = join_specs(o.tracers);
  t.res = fmt::format("{}x{}", o.width, o.height);
  cmd->add_option("--tracers", t.tracers,
                  "comma-separated tracers, e.g. cpu,embree:mode=packet16,simt; auto = cuda with a GPU, else cpu,simt")
      ->capture_default_str();
  cmd->add_option("--res", t.res, "resolution WxH")->capture_default_str();
  cmd->add_option("--frames", o.frames, "frames per scene")->capture_default_str();
  cmd->add_option("--seed", o.seed, "random seed")->capture_default_str();
  cmd->add_option("--repeat", o.repeats,
                  "timed repeats per batch, the median and its 95% interval reported (0: 9 on a GPU, 7 on the CPU, "
                  "1 for models and simulators)")
      ->capture_default_str();
  cmd->add_option("--out", o.out, "CSV file to write")->capture_default_str();
  cmd->add_flag("--force", o.force,
                "replace what --out (and its .partial) holds instead of resuming it or refusing other parameters");
  t.shard = o.shard.text();
  cmd->add_option("--shard", t.shard,
                  "I/N: measure only shard I (0-based) of N of the work list; join the N outputs with raycoh merge")
      ->capture_default_str();
}

void resolve_experiment(ExperimentOptions& o, const ExperimentText& t) {
  o.tracers = split_nonempty("--tracers", t.tracers);
  std::tie(o.width, o.height) = parse_res("--res", t.res);
  o.shard = parse_shard("--shard", t.shard);
}

}  // namespace raycoh
