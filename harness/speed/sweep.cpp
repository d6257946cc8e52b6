// `raycoh sweep`: noopt and one `ours` (or `contiguous`) method per tile size x group size cell, on one scene;
// prints the paper's Table 3 layout per tracer (MRay/s, or the timing model's modeled MRay/s for `simt`).
#include "harness/speed/sweep.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>

#include "core/error.h"
#include "generators/generator.h"
#include "harness/common/cli.h"
#include "harness/common/command.h"
#include "harness/speed/experiment_cli.h"
#include "harness/speed/table.h"

namespace raycoh {

namespace {

// The generator must group pixels (its parameter table has a group size k: ours, contiguous); K's range is the one
// that table states, and --groups is read through it.
const ParamSpec& group_size_row_of(const std::string& generator) {
  const ParamSpec* row = group_size_row(generator);
  if (!row)
    throw Error(fmt::format("--generator {}: sweep varies tile and group size; choose ours or contiguous", generator));
  return *row;
}

int parse_group_size(const std::string& generator, const std::string& text) {
  const ParamSpec& row = group_size_row_of(generator);
  return parse_int("--groups", text, static_cast<int>(row.lo), static_cast<int>(row.hi));
}

void check_sweep(const SweepOptions& o) {
  group_size_row_of(o.generator);
  if (o.tiles.empty()) throw Error("--tiles: empty list");
  if (o.groups.empty()) throw Error("--groups: empty list");
  for (const auto& tile : o.tiles) check_tile("--tiles", tile);
}

// One tracer's tile x K table.
void print_sweep(const SweepOptions& o, const SceneResult& r, const ResultKey& key,
                 const std::vector<std::vector<std::string>>& labels) {
  const ExperimentOptions& e = o.experiment;
  const auto& m = r.by_tracer.at(key);
  const std::string tl = key.label(true);
  if (m.at("noopt").hw.replayed) {  // cuda:counters=hw: replayed kernels, no speeds; the counters are in the CSV
    std::printf(
        "\n%s, tracer %s: MEASURED hardware counters only (kernels replayed by CUPTI: no speeds; hw_* columns "
        "of %s)\n",
        r.scene.c_str(), tl.c_str(), e.out.c_str());
    return;
  }
  // A modelling tracer's wall time is the model's: its cells are the timing model's modeled MRay/s.
  const bool model = m.at("noopt").model.any;
  auto value = [&](const Accumulated& a) { return model ? a.modeled_mray_s() : a.mray_s(); };
  const double base = value(m.at("noopt"));
  if (model)
    std::printf(
        "\n%s, tracer %s: MODELED GPU trace, not measured: modeled MRay/s of %s (ratio to noopt, %.1f modeled "
        "MRay/s); %dx%d, %d frame(s)\n\n",
        r.scene.c_str(), tl.c_str(), o.generator.c_str(), base, e.width, e.height, e.frames);
  else
    std::printf(
        "\n%s, tracer %s: secondary MRay/s of %s (ratio to noopt %.2f MRay/s [95%% interval]); %dx%d, %d "
        "frame(s)\n\n",
        r.scene.c_str(), tl.c_str(), o.generator.c_str(), base, e.width, e.height, e.frames);
  std::string header = "| (W,H) |", rule = "|---|";
  for (int k : o.groups) {
    header += fmt::format(" K = {} |", k);
    rule += "---:|";
  }
  std::printf("%s\n%s\n", header.c_str(), rule.c_str());
  for (size_t ti = 0; ti < o.tiles.size(); ++ti) {
    std::string line = fmt::format("| ({},{}) |", o.tiles[ti].first, o.tiles[ti].second);
    for (const std::string& label : labels[ti])
      line += label.empty() ? " — |"
              : model       ? " " + ratio_cell(value(m.at(label)), base) + " |"
                            : " " +
                            ratio_cell(value(m.at(label)), measured_ratio(m.at("noopt"), m.at(label), false),
                                       label == "noopt") +
                            " |";
    std::printf("%s\n", line.c_str());
  }
}

}  // namespace

int run_sweep(const SweepOptions& o, const Provenance& provenance) {
  check_sweep(o);
  ExperimentOptions e = o.experiment;
  e.methods = {{"noopt", {"noopt", ""}}};
  std::vector<std::vector<std::string>> labels(o.tiles.size());  // per tile, per K: method label ("" = no cell)
  for (size_t ti = 0; ti < o.tiles.size(); ++ti) {
    const auto [tw, th] = o.tiles[ti];
    for (int k : o.groups) {
      if (k > tw * th) {  // K larger than a tile is not a grouping: the cell stays empty
        labels[ti].push_back("");
        continue;
      }
      labels[ti].push_back(sweep_method_label(o.generator, tw, th, k));
      e.methods.push_back({labels[ti].back(), {o.generator, fmt::format("tile={}x{},k={}", tw, th, k)}});
    }
  }
  e.tracers = expand_auto(e.tracers);
  const std::vector<SceneResult> results = run_experiment(e, provenance);
  if (!e.shard.whole()) return print_shard_done(e, provenance);
  for (const ResultKey& key : results.front().tracers) print_sweep(o, results.front(), key, labels);
  std::printf("\nWrote %s (%s)\n", e.out.c_str(), provenance.git_revision.c_str());
  return 0;
}

BoundCommand bind_sweep(CLI::App& parent) {
  struct State {
    SweepOptions o;
    ExperimentText text;
    std::string scene, tiles, groups;
  };
  auto s = std::make_shared<State>();
  for (const auto& [w, h] : s->o.tiles) s->tiles += fmt::format("{}{}x{}", s->tiles.empty() ? "" : ",", w, h);
  for (int k : s->o.groups) s->groups += fmt::format("{}{}", s->groups.empty() ? "" : ",", k);
  CLI::App* cmd = parent.add_subcommand("sweep", "tile size x group size of ours (the paper's Table 3 layout)");
  cmd->add_option("--scene", s->scene, "scene")->required();
  cmd->add_option("--generator", s->o.generator, "ours or tile")->capture_default_str();
  cmd->add_option("--tiles", s->tiles, "comma-separated tile sizes WxH")->capture_default_str();
  cmd->add_option("--groups", s->groups, "comma-separated group sizes K")->capture_default_str();
  bind_experiment(cmd, s->o.experiment, s->text);
  return {cmd, [s](const Provenance& provenance) {
            s->o.experiment.scenes = {s->scene};
            s->o.tiles.clear();
            for (const PluginSpec& t : split_nonempty("--tiles", s->tiles))
              s->o.tiles.push_back(parse_res("--tiles", t.text()));
            s->o.groups.clear();
            for (const PluginSpec& k : split_nonempty("--groups", s->groups))
              s->o.groups.push_back(parse_group_size(s->o.generator, k.text()));
            resolve_experiment(s->o.experiment, s->text);
            return run_sweep(s->o, provenance);
          }};
}

}  // namespace raycoh
