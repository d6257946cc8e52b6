// `raycoh stability` (harness/stability.h): the command, its options, CSV and printed report; the measurement of
// one scene (its batches against the double-precision reference) is in harness/stability_measure.cpp. The cases
// and their rules are in docs/stability.md; the CSV's columns in results/README.md.
#include "harness/stability.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "core/error.h"
#include "encoders/encoder.h"
#include "generators/generator.h"
#include "harness/common/cli.h"
#include "harness/common/command.h"
#include "harness/common/exit_codes.h"
#include "harness/common/memory_check.h"
#include "records/record_csv.h"
#include "records/stability_row.h"

namespace raycoh {

bool StabilityReport::failed() const {
  return std::any_of(cases.begin(), cases.end(), [](const StabilityCase& c) { return c.failed(); });
}

const StabilityCase* StabilityReport::find(const std::string& batch, const std::string& name) const {
  for (const StabilityCase& c : cases)
    if (c.batch == batch && c.name == name) return &c;
  return nullptr;
}

namespace {

std::string status_of(const StabilityCase& c) { return !c.gated() ? "reported" : c.failed() ? "FAIL" : "ok"; }

void print_report(const StabilityReport& r) {
  std::printf(
      "\n%s (%s, %zu triangles)\n\n| batch | case | count | of | rate | threshold | status |\n"
      "|---|---|---:|---:|---:|---:|---|\n",
      r.scene.c_str(), r.spec.c_str(), r.triangles);
  for (const StabilityCase& c : r.cases)
    std::printf("| %s | %s | %zu | %zu | %.3g | %s | %s |\n", c.batch.c_str(), c.name.c_str(), c.count, c.of, c.rate(),
                c.gated() ? fmt::format("{:g}", c.threshold).c_str() : "-", status_of(c).c_str());
}

std::vector<std::pair<std::string, double>> parse_thresholds(const std::vector<std::string>& texts) {
  std::vector<std::pair<std::string, double>> out;
  const auto& names = stability_case_names();
  for (const std::string& t : texts) {
    const size_t eq = t.find('=');
    const std::string name = t.substr(0, eq);
    char* end = nullptr;
    const double v = eq == std::string::npos ? -1.0 : std::strtod(t.c_str() + eq + 1, &end);
    if (std::find(names.begin(), names.end(), name) == names.end() && name.rfind("key_degeneracy:", 0) != 0)
      throw Error(fmt::format("--threshold {}: unknown case '{}'; cases: {}", t, name, join(names)));
    if (eq == std::string::npos || end == t.c_str() + eq + 1 || *end != '\0' || !(v >= 0.0) || v > 1.0)
      throw Error(fmt::format("--threshold {}: expected CASE=RATE with RATE in [0, 1]", t));
    out.emplace_back(name, v);
  }
  return out;
}

void check_options(const StabilityOptions& o) {
  if (o.scenes.empty()) throw Error("--scene: empty list");
  if (o.width < 1 || o.width > 16384 || o.height < 1 || o.height > 16384)
    throw Error(fmt::format("--res {}x{}: width and height must be in [1, 16384]", o.width, o.height));
  if (o.frame < 0 || o.frame > (1 << 30)) throw Error(fmt::format("--frame {}: must be in [0, 2^30]", o.frame));
  if (o.generators.empty()) throw Error("--generators: empty list");
  for (const std::string& s : o.scenes) check_scene_spec("--scene", s);
  for (const PluginSpec& g : o.generators) make_generator(g);
  for (const PluginSpec& e : o.encoders)
    if (std::none_of(encoder_infos().begin(), encoder_infos().end(),
                     [&](const EncoderInfo& i) { return i.name == e.name; }))
      make_encoder(e, EncoderContext{});  // throws naming the valid encoders
  if (!o.out.empty()) {
    check_output_file("--out", o.out);
    if (!o.force && std::filesystem::exists(o.out))
      throw Error(fmt::format("--out {} already exists; pass --force to replace it, or choose another --out", o.out));
  }
  check_memory(fmt::format("--res {}x{}", o.width, o.height), experiment_bytes(o.width, o.height));
}

}  // namespace

const std::vector<std::string>& stability_case_names() {
  static const std::vector<std::string> names = {"non_finite",
                                                 "wrong_closest_hit",
                                                 "missed_hit",
                                                 "edge_graze",
                                                 "origin_behind_surface",
                                                 "origin_displaced",
                                                 "self_intersection",
                                                 "self_intersection_grazing",
                                                 "below_geometric_surface",
                                                 "shading_geometric_disagreement",
                                                 "reuse_discontinuity",
                                                 "key_degeneracy"};
  return names;
}

int run_stability(const StabilityOptions& o, const Provenance& provenance) {
  check_options(o);
  std::unique_ptr<RecordCsv<StabilityRow>> csv;
  if (!o.out.empty())
    csv = std::make_unique<RecordCsv<StabilityRow>>(o.out, stability_schema(), CsvWriter::Options::once(true));
  bool failed = false;
  for (const std::string& spec : o.scenes) {
    std::fprintf(stderr, "stability: %s ...\n", spec.c_str());
    const StabilityReport r = measure_stability(spec, o);
    print_report(r);
    failed = failed || r.failed();
    if (!csv) continue;
    for (const StabilityCase& c : r.cases) {
      StabilityRow row;
      row.scene = r.scene;
      row.spec = r.spec;
      row.triangles = r.triangles;
      row.batch = c.batch;
      row.name = c.name;
      row.count = c.count;
      row.of = c.of;
      row.rate = c.rate();
      row.threshold = c.gated() ? c.threshold : std::nan("");
      row.status = status_of(c);
      row.width = o.width;
      row.height = o.height;
      row.frame = o.frame;
      row.seed = o.seed;
      row.max_rays = o.max_rays;
      row.provenance = provenance;
      csv->write(row);
    }
  }
  if (csv) {
    csv->finish();
    std::printf("\nWrote %s\n", o.out.c_str());
  }
  if (failed) {
    std::fprintf(stderr, "raycoh: stability: a rate exceeds its threshold (FAIL rows above); exit code %d\n",
                 static_cast<int>(kExitThresholdExceeded));
    return kExitThresholdExceeded;
  }
  return 0;
}

BoundCommand bind_stability(CLI::App& parent) {
  struct State {
    StabilityOptions o;
    std::string scenes, generators, encoders, res;
    std::vector<std::string> thresholds;
  };
  auto s = std::make_shared<State>();
  s->generators = join_specs(s->o.generators);
  s->encoders = join_specs(s->o.encoders);
  s->res = fmt::format("{}x{}", s->o.width, s->o.height);
  CLI::App* cmd = parent.add_subcommand(
      "stability",
      "numerical stability of a scene's rays against a double-precision reference (exit 3 when a rate exceeds "
      "its threshold)");
  cmd->add_option("--scene,--scenes", s->scenes, "scene, or comma-separated scenes")->required();
  cmd->add_option("--generators", s->generators, "generators whose secondary batches are checked")
      ->capture_default_str();
  cmd->add_option("--encoders", s->encoders, "encoders whose key degeneracy is measured")->capture_default_str();
  cmd->add_option("--res", s->res, "resolution WxH")->capture_default_str();
  cmd->add_option("--seed", s->o.seed, "random seed")->capture_default_str();
  cmd->add_option("--frame", s->o.frame, "frame index")->capture_default_str();
  cmd->add_option("--max-rays", s->o.max_rays,
                  "rays per batch checked against the double reference, evenly spaced (0 = all)")
      ->capture_default_str();
  cmd->add_option("--threshold", s->thresholds,
                  "CASE=RATE: hold a case to another threshold (repeatable); CASE may be key_degeneracy");
  cmd->add_option("--out", s->o.out, "CSV file to write (one row per scene, batch and case)");
  cmd->add_flag("--force", s->o.force, "replace an existing --out");
  return {cmd, [s](const Provenance& provenance) {
            s->o.scenes = split_scenes("--scene", s->scenes);
            s->o.generators = split_nonempty("--generators", s->generators);
            s->o.encoders = s->encoders.empty() ? std::vector<PluginSpec>{} : split_nonempty("--encoders", s->encoders);
            std::tie(s->o.width, s->o.height) = parse_res("--res", s->res);
            s->o.thresholds = parse_thresholds(s->thresholds);
            return run_stability(s->o, provenance);
          }};
}

}  // namespace raycoh
