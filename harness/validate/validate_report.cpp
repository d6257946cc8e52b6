#include "harness/validate/validate_report.h"

#include <fmt/format.h>

#include <cmath>

#include "harness/validate/validate_paper.h"

namespace raycoh {
namespace {

std::string pct(double e) { return std::isnan(e) ? "—" : fmt::format("{:+.0f}%", 100 * e); }

bool measured(const ValidateRow& v) { return v.kind != "modeled"; }
double ours_mray_s(const ValidateRow& v) { return measured(v) ? v.measured_mray_s : v.modeled_mray_s; }
double ours_ratio(const ValidateRow& v) { return measured(v) ? v.measured_ratio : v.modeled_ratio; }

// "1.52", or a measured "1.52 [1.48, 1.55]".
std::string ratio_cell(const ValidateRow& v) {
  if (!measured(v) || std::isnan(v.ratio_lo)) return fmt::format("{:.2f}", ours_ratio(v));
  return fmt::format("{:.2f} [{:.2f}, {:.2f}]", ours_ratio(v), v.ratio_lo, v.ratio_hi);
}

std::string heading(const std::string& order, int width, int height, const ValidateRow& first) {
  const std::string what =
      first.kind == "modeled"
          ? fmt::format("Model: `{}` (MODELED, not measured).", first.tracer_params)
          : fmt::format(
                "{} on {} (`{}`): trace MRay/s, the median of the row's repeats; our ratio to NoOpt with its "
                "paired 95% interval (docs/statistics.md).",
                first.kind == "measured" ? "MEASURED" : "SIMULATED", first.provenance.device, first.tracer_params);
  return fmt::format(
      "## {} beside the paper: {}x{}, ours in {} order\n\n{} Paper: Liu et al. 2024, measured on an RTX 3060. "
      "Ratio error = our ratio / the paper's ratio - 1.\n",
      first.kind == "modeled"    ? "The GPU timing model"
      : first.kind == "measured" ? "Measured speeds"
                                 : "Simulated speeds (GPGPU-Sim, not hardware)",
      width, height, order, what);
}

std::string table1(const std::vector<ValidateRow>& rows, const std::string& column) {
  const bool m = measured(rows.front());
  std::string s = fmt::format(
      "\n### Table 1, {} column ({})\n\n| method | paper MRay/s | paper ratio | our MRay/s | our ratio | ratio error | "
      "{} |\n|---|---:|---:|---:|---:|---:|---|\n",
      column,
      [&] {
        for (const ValidateRow& v : rows)
          if (v.paper_scene == column) return v.scene;
        return std::string();
      }(),
      m ? "paper in our interval" : "limiter");
  for (const ValidateRow& v : rows)
    if (v.table == "table1" && v.paper_scene == column)
      s += fmt::format("| {} | {:.1f} | {:.2f} | {:.4g} | {} | {} | {} |\n", v.paper_row, v.paper_mray_s, v.paper_ratio,
                       ours_mray_s(v), ratio_cell(v), pct(v.ratio_error), m ? v.paper_in_interval : v.limiter);
  return s;
}

std::string table3(const std::vector<ValidateRow>& rows) {
  std::string s =
      "\n### Table 3 (ours on Sibenik): our ratio / the paper's (ratio error)\n\n| (W,H) | K = 8 | K = 16 | K = 32 | "
      "K = 64 |\n|---|---:|---:|---:|---:|\n";
  for (const auto& t : paper::kTiles) {
    s += fmt::format("| ({},{}) |", t[0], t[1]);
    for (int k : paper::kGroups)
      for (const ValidateRow& v : rows)
        if (v.table == "table3" && v.tile == fmt::format("{}x{}", t[0], t[1]) && v.k == k)
          s += fmt::format(" {} / {:.2f} ({}) |", ratio_cell(v), v.paper_ratio, pct(v.ratio_error));
    s += "\n";
  }
  return s;
}

const ValidateRow* find(const std::vector<ValidateRow>& rows, const std::string& table, const std::string& row) {
  for (const ValidateRow& v : rows)
    if (v.table == table && v.row == row && (table != "table1" || v.paper_scene == "Sibenik")) return &v;
  return nullptr;
}

std::string goals(const std::vector<ValidateRow>& rows) {
  int within = 0, cells = 0, inside = 0, with_interval = 0;
  double worst = 0;
  for (const ValidateRow& v : rows) {
    if (std::isnan(v.ratio_error) || v.row == "noopt") continue;
    ++cells;
    within += std::fabs(v.ratio_error) <= 0.15;
    worst = std::max(worst, std::fabs(v.ratio_error));
    with_interval += !v.paper_in_interval.empty();
    inside += v.paper_in_interval == "yes";
  }
  const ValidateRow* noopt = find(rows, "table1", "noopt");
  const ValidateRow* k32 = find(rows, "table3", "ours:tile=8x8,k=32");
  const ValidateRow* k64 = find(rows, "table3", "ours:tile=8x8,k=64");
  const ValidateRow* bound = find(rows, "bound", "primary");
  std::string s = fmt::format(
      "\n### Goals (docs/simt-model.md, section 4)\n\n- ratios within +-15% of the paper's: {} "
      "of {} cells (largest error {:.0f}%)\n",
      within, cells, 100 * worst);
  if (with_interval > 0)
    s += fmt::format("- the paper's ratio inside our 95% interval: {} of {} cells\n", inside, with_interval);
  if (noopt && !measured(*noopt))
    s += fmt::format("- modeled NoOpt {:.1f} MRay/s vs the paper's {:.1f} ({}; goal +-30%)\n", noopt->modeled_mray_s,
                     noopt->paper_mray_s, pct(noopt->modeled_mray_s / noopt->paper_mray_s - 1));
  else if (noopt)
    s += fmt::format("- NoOpt {:.1f} MRay/s {} on another GPU than the paper's: MRay/s are not compared, ratios are\n",
                     noopt->measured_mray_s, noopt->kind == "measured" ? "measured" : "simulated (GPGPU-Sim)");
  if (k32 && k64)
    s += fmt::format("- saturation, K = 32 -> 64 at (8,8): ours {:+.1f}%, paper {:+.1f}% (goal under 10%)\n",
                     100 * (ours_mray_s(*k64) / ours_mray_s(*k32) - 1),
                     100 * (k64->paper_mray_s / k32->paper_mray_s - 1));
  if (bound)
    s += fmt::format("- primary rays (not in the paper): {:.4g} MRay/s, {}x NoOpt\n", ours_mray_s(*bound),
                     ratio_cell(*bound));
  return s;
}

}  // namespace

std::string validate_report(const std::string& order, int width, int height, const std::vector<ValidateRow>& rows) {
  if (rows.empty()) return "";
  std::string s = heading(order, width, height, rows.front());
  for (const paper::Table1Column& c : paper::kTable1)
    for (const ValidateRow& v : rows)
      if (v.paper_scene == c.paper_scene) {
        s += table1(rows, c.paper_scene);
        break;
      }
  return s + table3(rows) + goals(rows);
}

}  // namespace raycoh
