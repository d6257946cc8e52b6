// `raycoh validate`: the GPU timing model (the `simt` tracer) beside the paper it must predict, cell by cell.
// Runs the paper's Table 1 methods (Sibenik column) and the 16 cells of its Table 3 on one scene with
// `simt:preset=<preset>`, and prints and writes, per cell, the paper's measured MRay/s and ratio to NoOpt, the
// model's modeled MRay/s and ratio, and the ratio's relative error; then the goals of the model (docs/simt-model.md,
// section 4). The paper's figures are the model's validation set: they are only compared against, never used to
// set a parameter. The experiment rows go to `<out>.rows.csv` (resumable, results/README.md), the comparison to
// `<out>` (schema in results/README.md, "validate") and a Markdown copy of the printout to `<out>.md`.
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
#include "harness/cli.h"
#include "harness/command.h"
#include "harness/exit_codes.h"
#include "harness/table.h"
#include "records/record_csv.h"
#include "records/recorded_columns.h"
#include "records/validate_row.h"

namespace raycoh {
namespace {

// Liu et al., "Generate Coherent Rays Directly", Eurographics 2024, measured on an RTX 3060 at 1920x1080 (the
// paper's own tables): Table 1's Sibenik column (MRay/s, trace of the secondary rays) and Table 3 (ours on
// Sibenik, tile W x H, group size K).
struct PaperCell {
  const char* row;    // our method label
  const char* paper;  // the paper's row name
  double mray_s;
};
const PaperCell kTable1[] = {
    {"noopt", "NoOpt", 154.7},
    {"ours:tile=8x8,k=8", "Ours", 278.5},
    {"noopt+mlhcc", "MLHCC32", 218.5},
    {"noopt+twopoint", "TwoPoint", 217.9},
    {"noopt+aila", "AilaCompact", 208.9},
    {"noopt+reis", "Reis", 183.2},
    {"noopt+origin", "Origin", 165.4},
};
const int kTiles[4][2] = {{8, 8}, {16, 8}, {16, 16}, {32, 8}};
const int kGroups[4] = {8, 16, 32, 64};
const double kTable3[4][4] = {{278.5, 303.9, 378.0, 379.4},
                              {234.1, 290.4, 338.9, 337.7},
                              {232.5, 273.9, 305.2, 306.6},
                              {227.1, 255.0, 298.9, 298.5}};
constexpr double kPaperNoOpt = 154.7;

struct ValidateOptions {
  std::string scene = "../shared/scenes/sibenik";
  std::string preset = "rtx3060";
  std::string tracer_params;   // extra simt parameters, e.g. kernel=simple (what-if runs)
  std::string order = "tile";  // batch order of `ours` (docs/design.md section 1): tile | group | scanline
  int width = 1920, height = 1080, frames = 1;
  uint32_t seed = 1;
  std::string out = "raycoh-validate.csv";
  bool force = false;
};

std::string cell_label(int w, int h, int k) { return sweep_method_label("ours", w, h, k); }

ExperimentOptions experiment_of(const ValidateOptions& o) {
  ExperimentOptions e;
  e.scenes = {o.scene};
  e.tracers = {{"simt", "preset=" + o.preset + (o.tracer_params.empty() ? "" : "," + o.tracer_params)}};
  e.width = o.width;
  e.height = o.height;
  e.frames = o.frames;
  e.seed = o.seed;
  e.repeats = 1;
  e.out = o.out + ".rows.csv";
  for (const char* enc : {"", "origin", "reis", "aila", "twopoint", "mlhcc"})
    e.methods.push_back({*enc ? fmt::format("noopt+{}", enc) : "noopt", {"noopt", ""}, {*enc ? enc : "none", ""}});
  for (const auto& t : kTiles)
    for (int k : kGroups)
      e.methods.push_back(
          {cell_label(t[0], t[1], k), {"ours", fmt::format("tile={}x{},k={},order={}", t[0], t[1], k, o.order)}});
  return e;
}

std::vector<ValidateRow> compare(const ValidateOptions& o, const SceneResult& r, const Provenance& p) {
  const auto& m = r.by_tracer.at(r.tracer_labels.front());
  const double base = m.at("noopt").modeled_mray_s();
  auto row = [&](const std::string& table, const std::string& label, const std::string& paper_row, double paper) {
    ValidateRow v;
    v.table = table;
    v.row = label;
    v.paper_row = paper_row;
    v.paper_mray_s = paper;
    v.paper_ratio = paper / kPaperNoOpt;
    v.modeled_mray_s = m.at(label).modeled_mray_s();
    v.modeled_ratio = v.modeled_mray_s / base;
    v.ratio_error = std::isnan(paper) ? NAN : v.modeled_ratio / v.paper_ratio - 1.0;
    v.limiter = m.at(label).modeled_limiter;
    v.scene = r.scene;
    v.preset = o.preset;
    v.tracer_params = r.tracer_labels.front();
    v.order = o.order;
    v.width = o.width;
    v.height = o.height;
    v.provenance = p;
    return v;
  };
  std::vector<ValidateRow> rows;
  for (const PaperCell& c : kTable1) rows.push_back(row("table1", c.row, c.paper, c.mray_s));
  for (int ti = 0; ti < 4; ++ti)
    for (int ki = 0; ki < 4; ++ki) {
      const auto& t = kTiles[ti];
      ValidateRow v = row("table3", cell_label(t[0], t[1], kGroups[ki]),
                          fmt::format("({},{}) K={}", t[0], t[1], kGroups[ki]), kTable3[ti][ki]);
      v.tile = fmt::format("{}x{}", t[0], t[1]);
      v.k = kGroups[ki];
      rows.push_back(v);
    }
  rows.push_back(row("bound", "primary", "", NAN));
  return rows;
}

std::string pct(double e) { return std::isnan(e) ? "—" : fmt::format("{:+.0f}%", 100 * e); }

// The printout (also written as <out>.md).
std::string report(const ValidateOptions& o, const std::vector<ValidateRow>& rows) {
  std::string s = fmt::format(
      "## The GPU timing model against the paper: {} at {}x{}, ours in {} order\n\nModel: `{}` (MODELED, not "
      "measured). Paper: Liu et al. 2024, measured on an RTX 3060. Ratio error = modeled ratio / paper ratio - 1."
      "\n\n"
      "### Table 1 (Sibenik column)\n\n| method | paper MRay/s | paper ratio | modeled MRay/s | modeled ratio | "
      "ratio error | limiter |\n|---|---:|---:|---:|---:|---:|---|\n",
      rows.front().scene, o.width, o.height, o.order, rows.front().tracer_params);
  int within = 0, cells = 0;
  double worst = 0;
  for (const ValidateRow& v : rows) {
    if (v.table == "table1")
      s += fmt::format("| {} | {:.1f} | {:.2f} | {:.1f} | {:.2f} | {} | {} |\n", v.paper_row, v.paper_mray_s,
                       v.paper_ratio, v.modeled_mray_s, v.modeled_ratio, pct(v.ratio_error), v.limiter);
    if (!std::isnan(v.ratio_error) && v.row != "noopt") {
      ++cells;
      within += std::fabs(v.ratio_error) <= 0.15;
      worst = std::max(worst, std::fabs(v.ratio_error));
    }
  }
  s += "\n### Table 3 (ours on Sibenik): modeled ratio / paper ratio (ratio error)\n\n| (W,H) | K = 8 | K = 16 | "
       "K = 32 | K = 64 |\n|---|---:|---:|---:|---:|\n";
  for (int ti = 0; ti < 4; ++ti) {
    s += fmt::format("| ({},{}) |", kTiles[ti][0], kTiles[ti][1]);
    for (int ki = 0; ki < 4; ++ki) {
      const ValidateRow& v = rows[std::size(kTable1) + ti * 4 + ki];
      s += fmt::format(" {:.2f} / {:.2f} ({}) |", v.modeled_ratio, v.paper_ratio, pct(v.ratio_error));
    }
    s += "\n";
  }
  const ValidateRow& noopt = rows.front();
  const ValidateRow& k32 = rows[std::size(kTable1) + 2];
  const ValidateRow& k64 = rows[std::size(kTable1) + 3];
  s += fmt::format(
      "\n### Goals (docs/simt-model.md, section 4)\n\n- ratios within +-15% of the paper's: {} of {} cells (largest "
      "error {:.0f}%)\n- modeled NoOpt {:.1f} MRay/s vs the paper's {:.1f} ({}; goal +-30%)\n- saturation, K = 32 -> "
      "64 at (8,8): modeled {:+.1f}%, paper {:+.1f}% (goal under 10%)\n- primary rays (not in the paper): "
      "{:.1f} modeled MRay/s, {:.2f}x NoOpt\n",
      within, cells, 100 * worst, noopt.modeled_mray_s, kPaperNoOpt, pct(noopt.modeled_mray_s / kPaperNoOpt - 1),
      100 * (k64.modeled_mray_s / k32.modeled_mray_s - 1), 100 * (k64.paper_mray_s / k32.paper_mray_s - 1),
      rows.back().modeled_mray_s, rows.back().modeled_ratio);
  return s;
}

void check(const ValidateOptions& o) {
  // A built-in scene name runs (a quick check of the command); a path must exist.
  const bool path = o.scene.find_first_of("/.") != std::string::npos;
  if (path && !std::filesystem::exists(o.scene))
    throw Error(
        fmt::format("--scene {}: no such file or folder; validate compares with the paper's Sibenik: pass "
                    "the path of ../shared/scenes/sibenik (McGuire's Sibenik Cathedral)",
                    o.scene));
  if (o.frames < 1 || o.frames > 100) throw Error(fmt::format("--frames {}: must be in [1, 100]", o.frames));
}

int run_validate(const ValidateOptions& o, const Provenance& provenance) {
  check(o);
  RecordCsv<ValidateRow> csv(o.out, validate_schema(), CsvWriter::Options::once(o.force, same_command(provenance)));
  if (csv.already_complete()) {
    std::printf(
        "%s already holds the result of this same command (same code revision): nothing to do; pass --force "
        "to model it again\n",
        o.out.c_str());
    return 0;
  }
  ExperimentOptions e = experiment_of(o);
  e.force = o.force;
  const std::vector<SceneResult> results = run_experiment(e, provenance);
  const std::vector<ValidateRow> rows = compare(o, results.front(), provenance);
  for (const ValidateRow& v : rows) csv.write(v);
  const std::string text = report(o, rows);
  write_file_atomically(o.out + ".md", text);
  csv.finish();
  std::fputs(("\n" + text).c_str(), stdout);
  std::printf("\nWrote %s, %s.md and %s.rows.csv (%s)\n", o.out.c_str(), o.out.c_str(), o.out.c_str(),
              provenance.git_revision.c_str());
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
      "validate", "the GPU timing model (simt) beside the paper's Table 1 (Sibenik) and Table 3, cell by cell");
  cmd->add_option("--scene", s->o.scene, "the Sibenik scene (file or folder)")->capture_default_str();
  cmd->add_option("--preset", s->o.preset, "simt preset of the modelled GPU")->capture_default_str();
  cmd->add_option("--tracer-params", s->o.tracer_params, "more simt parameters, e.g. kernel=simple");
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
