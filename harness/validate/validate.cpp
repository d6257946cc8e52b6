// `raycoh validate`: a GPU timing figure beside the paper it must reproduce, cell by cell. Runs the paper's Table 1
// methods and the 16 cells of its Table 3 on Sibenik, and with --stand-ins the Table 1 methods on the scenes that
// stand in for the paper's other four columns (harness/validate/validate_paper.h), with the `simt` model
// (simt:preset=<preset>, MODELED) or a GPU (--tracer cuda: MEASURED, or SIMULATED under GPGPU-Sim), and prints and
// writes, per cell, the paper's MRay/s and ratio to NoOpt, ours (a measured ratio with its paired 95% interval and
// whether the paper's ratio lies in it) and the ratio's relative error; then the goals. The paper's figures are
// the validation set: compared against, never used to set a parameter. The experiment rows go to `<out>.rows.csv`
// and `<out>.table1-rows.csv` (resumable, results/README.md), the comparison to `<out>` (results/README.md,
// "validate") and a Markdown copy of the printout to `<out>.md`.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <tuple>

#include "core/durable_file.h"
#include "core/error.h"
#include "harness/common/cli.h"
#include "harness/common/command.h"
#include "harness/common/exit_codes.h"
#include "harness/speed/table.h"
#include "harness/validate/validate_paper.h"
#include "harness/validate/validate_report.h"
#include "records/record_csv.h"
#include "records/recorded_columns.h"
#include "records/validate_row.h"
#include "tracers/hw_counters.h"

namespace raycoh {
namespace {

struct ValidateOptions {
  std::string scene = "../shared/scenes/sibenik";
  std::string preset = "rtx3060";
  std::string tracer_params;   // extra tracer parameters, e.g. kernel=simple (what-if runs of simt)
  std::string tracer;          // --tracer: "" (simt:preset=<preset>) or a measuring tracer, e.g. cuda
  std::string stand_ins;       // --stand-ins: folder of Table 1's other scenes (validate_paper.h), "" for Sibenik only
  std::string order = "tile";  // batch order of `ours` (docs/design.md section 1): tile | group | scanline
  int width = 1920, height = 1080, frames = 1;
  uint32_t seed = 1;
  std::string out = "raycoh-validate.csv";
  bool force = false;
};

std::string cell_label(int w, int h, int k) { return sweep_method_label("ours", w, h, k); }

bool modeled(const ValidateOptions& o) { return o.tracer.empty() || o.tracer.rfind("simt", 0) == 0; }

PluginSpec tracer_of(const ValidateOptions& o) {
  if (o.tracer.empty()) return {"simt", "preset=" + o.preset + (o.tracer_params.empty() ? "" : "," + o.tracer_params)};
  PluginSpec t = parse_plugin_spec(o.tracer);
  if (!o.tracer_params.empty()) t.params += (t.params.empty() ? "" : ",") + o.tracer_params;
  return t;
}

// What our figures are: modeled (simt), simulated (a GPU simulator) or measured.
std::string kind_of(const ValidateOptions& o) {
  if (modeled(o)) return "modeled";
  return simulated_device(tracer_of(o)) ? "simulated" : "measured";
}

// Table 1's methods, and with `table3` the 16 cells of Table 3 in `order`.
ExperimentOptions experiment_of(const ValidateOptions& o, std::vector<std::string> scenes, bool table3,
                                const std::string& out) {
  ExperimentOptions e;
  e.scenes = std::move(scenes);
  e.tracers = {tracer_of(o)};
  e.width = o.width;
  e.height = o.height;
  e.frames = o.frames;
  e.seed = o.seed;
  e.repeats = modeled(o) ? 1 : 0;  // a GPU: its default repeats, for the intervals
  e.out = out;
  e.force = o.force;
  for (const char* enc : {"", "origin", "reis", "aila", "twopoint", "mlhcc"})
    e.methods.push_back({*enc ? fmt::format("noopt+{}", enc) : "noopt", {"noopt", ""}, {*enc ? enc : "none", ""}});
  e.methods.push_back({"ours:tile=8x8,k=8", {"ours", fmt::format("tile=8x8,k=8,order={}", o.order)}});
  for (int ti = 0; table3 && ti < 4; ++ti)
    for (int k : paper::kGroups) {
      const int w = paper::kTiles[ti][0], h = paper::kTiles[ti][1];
      if (w == 8 && h == 8 && k == 8) continue;  // Table 1's Ours
      e.methods.push_back({cell_label(w, h, k), {"ours", fmt::format("tile={}x{},k={},order={}", w, h, k, o.order)}});
    }
  return e;
}

// One compared cell of scene result r (the paper's column `col`) for our method `label`.
ValidateRow compare_cell(const ValidateOptions& o, const SceneResult& r, const paper::Table1Column& col,
                         const std::string& label, double paper_mray_s) {
  const auto& m = r.by_tracer.at(r.tracers.front());
  ValidateRow v;
  v.row = label;
  v.paper_scene = col.paper_scene;
  v.paper_mray_s = paper_mray_s;
  v.paper_ratio = paper_mray_s / col.mray_s[0];
  v.kind = kind_of(o);
  double ours = 0;
  if (v.kind == "modeled") {
    v.modeled_mray_s = m.at(label).modeled_mray_s();
    v.modeled_ratio = ours = v.modeled_mray_s / m.at("noopt").modeled_mray_s();
    v.limiter = m.at(label).model.limiter;
  } else {
    const SpeedRatio ratio = measured_ratio(m.at("noopt"), m.at(label), false);
    v.measured_mray_s = m.at(label).mray_s();
    v.measured_ratio = ours = ratio.ratio;
    if (ratio.has_interval && label != "noopt") {  // noopt is the base: 1 by definition
      v.ratio_lo = ratio.lo;
      v.ratio_hi = ratio.hi;
      if (!std::isnan(v.paper_ratio))
        v.paper_in_interval = ratio.lo <= v.paper_ratio && v.paper_ratio <= ratio.hi ? "yes" : "no";
    }
  }
  v.ratio_error = std::isnan(v.paper_ratio) ? NAN : ours / v.paper_ratio - 1.0;
  v.scene = r.scene;
  v.preset = modeled(o) ? o.preset : "";
  v.tracer_params = r.tracers.front().label(true);
  v.order = o.order;
  v.width = o.width;
  v.height = o.height;
  return v;
}

// Table 1's rows of one column; for Sibenik also Table 3's cells and the primary bound.
void compare(const ValidateOptions& o, const SceneResult& r, const paper::Table1Column& col, bool table3,
             std::vector<ValidateRow>& rows) {
  for (int i = 0; i < paper::kTable1RowCount; ++i) {
    ValidateRow v = compare_cell(o, r, col, paper::kTable1Rows[i].row, col.mray_s[i]);
    v.table = "table1";
    v.paper_row = paper::kTable1Rows[i].paper;
    rows.push_back(v);
  }
  if (!table3) return;
  for (int ti = 0; ti < 4; ++ti)
    for (int ki = 0; ki < 4; ++ki) {
      const auto& t = paper::kTiles[ti];
      ValidateRow v = compare_cell(o, r, col, cell_label(t[0], t[1], paper::kGroups[ki]), paper::kTable3[ti][ki]);
      v.table = "table3";
      v.paper_row = fmt::format("({},{}) K={}", t[0], t[1], paper::kGroups[ki]);
      v.tile = fmt::format("{}x{}", t[0], t[1]);
      v.k = paper::kGroups[ki];
      rows.push_back(v);
    }
  ValidateRow bound = compare_cell(o, r, col, "primary", NAN);
  bound.table = "bound";
  rows.push_back(bound);
}

void check(const ValidateOptions& o) {
  // A built-in scene name runs (a quick check of the command); a path must exist.
  const bool path = o.scene.find_first_of("/.") != std::string::npos;
  if (path && !std::filesystem::exists(o.scene))
    throw Error(
        fmt::format("--scene {}: no such file or folder; validate compares with the paper's Sibenik: pass "
                    "the path of the sibenik scene (README, \"Real scenes\")",
                    o.scene));
  if (o.frames < 1 || o.frames > 100) throw Error(fmt::format("--frames {}: must be in [1, 100]", o.frames));
  if (!o.stand_ins.empty())
    for (const paper::Table1Column& c : paper::kTable1)
      if (c.stand_in != std::string("sibenik") &&
          !std::filesystem::exists(std::filesystem::path(o.stand_ins) / c.stand_in))
        throw Error(
            fmt::format("--stand-ins {}: no {} in it (the stand-in for the paper's {}); the folder must hold "
                        "country_kitchen, contemporary_bathroom, modern_living_room and lost_empire",
                        o.stand_ins, c.stand_in, c.paper_scene));
}

// Runs the experiments and compares: Sibenik (Tables 1 and 3), then the stand-ins (Table 1).
std::vector<ValidateRow> measure(const ValidateOptions& o, const Provenance& provenance) {
  std::vector<ValidateRow> rows;
  const std::vector<SceneResult> sibenik =
      run_experiment(experiment_of(o, {o.scene}, true, o.out + ".rows.csv"), provenance);
  compare(o, sibenik.front(), paper::kTable1[paper::kSibenik], true, rows);
  if (o.stand_ins.empty()) return rows;
  std::vector<std::string> scenes;
  std::vector<const paper::Table1Column*> columns;
  for (const paper::Table1Column& c : paper::kTable1)
    if (c.stand_in != std::string("sibenik")) {
      scenes.push_back((std::filesystem::path(o.stand_ins) / c.stand_in).string());
      columns.push_back(&c);
    }
  const std::vector<SceneResult> others =
      run_experiment(experiment_of(o, scenes, false, o.out + ".table1-rows.csv"), provenance);
  for (size_t i = 0; i < others.size(); ++i) compare(o, others[i], *columns[i], false, rows);
  return rows;
}

int run_validate(const ValidateOptions& o, const Provenance& provenance) {
  check(o);
  if (const std::string why = hw_counters_refusal("--tracer", tracer_of(o).params); !why.empty()) throw Error(why);
  RecordCsv<ValidateRow> csv(o.out, validate_schema(), CsvWriter::Options::once(o.force, same_command(provenance)));
  if (csv.already_complete()) {
    std::printf(
        "%s already holds the result of this same command (same code revision): nothing to do; pass --force "
        "to run it again\n",
        o.out.c_str());
    return 0;
  }
  std::vector<ValidateRow> rows = measure(o, provenance);
  for (ValidateRow& v : rows) {
    v.provenance = provenance;
    v.provenance.device = device_of(tracer_of(o));
    csv.write(v);
  }
  const std::string text = validate_report(o.order, o.width, o.height, rows);
  write_file_atomically(o.out + ".md", text);
  csv.finish();
  std::fputs(("\n" + text).c_str(), stdout);
  std::printf("\nWrote %s, %s.md and its rows (%s)\n", o.out.c_str(), o.out.c_str(), provenance.git_revision.c_str());
  return 0;
}

}  // namespace

BoundCommand bind_validate(CLI::App& parent) {
  struct State {
    ValidateOptions o;
    std::string res;
  };
  auto s = std::make_shared<State>();
  s->res = fmt::format("{}x{}", s->o.width, s->o.height);
  CLI::App* cmd = parent.add_subcommand(
      "validate",
      "the GPU timing model (simt) or a GPU beside the paper's Table 1 (Sibenik, or all five scenes) and Table 3");
  cmd->add_option("--scene", s->o.scene, "the Sibenik scene (file or folder)")->capture_default_str();
  cmd->add_option("--preset", s->o.preset, "simt preset of the modelled GPU")->capture_default_str();
  cmd->add_option("--tracer", s->o.tracer,
                  "measure on a GPU instead of the model: cuda[:params] (measured ratios with 95% intervals)");
  cmd->add_option("--tracer-params", s->o.tracer_params, "more tracer parameters, e.g. kernel=simple");
  cmd->add_option("--stand-ins", s->o.stand_ins,
                  "folder holding the scenes that stand in for Table 1's other columns (country_kitchen, "
                  "contemporary_bathroom, modern_living_room, lost_empire): Table 1 on all five");
  cmd->add_option("--order", s->o.order, "batch order of ours: tile (the default order), group or scanline")
      ->capture_default_str();
  cmd->add_option("--res", s->res, "resolution WxH")->capture_default_str();
  cmd->add_option("--frames", s->o.frames, "frames (the model is deterministic per frame)")->capture_default_str();
  cmd->add_option("--seed", s->o.seed, "seed")->capture_default_str();
  cmd->add_option("--out", s->o.out, "comparison CSV (also <out>.md and <out>.rows.csv)")->capture_default_str();
  cmd->add_flag("--force", s->o.force, "replace an existing --out");
  return {cmd, [s](const Provenance& provenance) {
            std::tie(s->o.width, s->o.height) = parse_res("--res", s->res);
            return run_validate(s->o, provenance);
          }};
}

}  // namespace raycoh
