// `raycoh report CSV...`: one self-contained HTML page (figures as inline SVG, images as data URIs, no scripts, no
// external files) and a Markdown summary, from the result CSVs of `table`, `sweep`, `converge` and `quality`.
//
// Figures: the paper's Table 1 layout as bars of the ratio to noopt (generators as groups and hues, encoders as
// shades of their generator's hue, axis from 0), trace only and end to end, per tracer (`simt` figures modeled,
// and labelled so); Table 3 heatmaps (tile down, K across); error against CPU time (wall clock and trace) from
// converge curves, log-log; the quality images side by side; provenance at the bottom. Colours: Okabe & Ito's
// colour-blind-safe palette, and a light-to-dark blue ramp for the heatmaps, every cell also printed as a number.
// The CSVs are read by the results layer (records/result_csv.h); figures: harness/report/report_figures.cpp; sections:
// harness/report/report_sections.cpp.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>

#include "core/durable_file.h"
#include "core/error.h"
#include "harness/common/command.h"
#include "harness/report/report_parts.h"

namespace raycoh {

using namespace report_detail;

namespace {

const char* const kStyle = R"(<style>
body{font-family:sans-serif;max-width:1400px;margin:1em auto;padding:0 1em;color:#222}
h2{border-bottom:1px solid #ccc;padding-bottom:.2em;margin-top:1.6em}
.figs{display:flex;flex-wrap:wrap;gap:16px;align-items:flex-start}
.imgs{display:flex;flex-wrap:wrap;gap:8px}
figure{margin:0}figure img{image-rendering:pixelated;width:240px;border:1px solid #ccc}
.crop{width:240px;overflow:hidden;position:relative;border:1px solid #ccc}
.crop img{position:absolute;width:720px;left:-240px;top:-100%;border:0}
figcaption{font-size:12px;text-align:center}
table{border-collapse:collapse;font-size:13px}td,th{border:1px solid #ccc;padding:2px 8px;text-align:right}
td:first-child,th:first-child{text-align:left}
.wide{overflow-x:auto}.win{font-weight:bold}.note{color:#555;font-size:13px}footer{margin-top:2em;font-size:12px;color:#555}
</style>)";

}  // namespace

int run_report(const std::vector<std::string>& inputs, const std::string& out, const std::string& md,
               const Provenance& provenance) {
  if (inputs.empty()) throw Error("report: name at least one result CSV (e.g. raycoh report results/*.csv)");
  check_output_file("--out", out);
  check_output_file("--md", md);
  std::vector<std::pair<ResultCsv, ResultKind>> csvs;
  for (const std::string& path : inputs) {
    ResultCsv c = read_result_csv(path);
    const ResultKind k = result_kind(c);
    csvs.emplace_back(std::move(c), k);
  }
  Page p;
  p.md =
      "# raycoh report\n\nSpeeds are ratios to noopt (higher is faster). `simt` figures are MODELED on the GPU "
      "model (docs/simt-model.md), never measured; every other tracer's are measured on the CPU named below.\n\n";
  static const char* names[] = {"table",   "sweep",    "converge curve", "converge summary",
                                "quality", "validate", "stability",      "tune"};
  // Tables first, then sweeps, quality, convergence and the model's validation, whatever the argument order.
  for (ResultKind k :
       {ResultKind::Table, ResultKind::Sweep, ResultKind::Quality, ResultKind::Converge, ResultKind::ConvergeSummary,
        ResultKind::Validate, ResultKind::Stability, ResultKind::Tune, ResultKind::TuneConfirm})
    for (const auto& [c, kind] : csvs) {
      if (kind != k) continue;
      if (k == ResultKind::Table) add_table(p, c);
      if (k == ResultKind::Sweep) add_sweep(p, c);
      if (k == ResultKind::Quality) add_quality(p, c);
      if (k == ResultKind::Converge) add_converge(p, c);
      if (k == ResultKind::ConvergeSummary) add_converge_summary(p, c);
      if (k == ResultKind::Validate) add_validate(p, c);
      if (k == ResultKind::Stability) add_stability(p, c);
      if (k == ResultKind::Tune) add_tune(p, c);
      if (k == ResultKind::TuneConfirm) add_tune_confirm(p, c);
      p.provenance.push_back(provenance_of(c, names[static_cast<int>(k)]));
    }
  std::string html = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>raycoh report</title>\n";
  html += kStyle;
  html +=
      "</head><body>\n<h1>raycoh report</h1>\n<p class=\"note\">Which way of making secondary rays coherent pays "
      "off: generating them coherent (<b>ours</b>, Liu et al. 2024; <b>contiguous</b> and <b>direct</b> are its "
      "ablations) or reordering NoOpt's rays by sorting on a key (<b>noopt+encoder</b>). Bars are speeds divided by "
      "<b>noopt</b>'s on the same scene and tracer, axes from 0, the dashed line at 1. <b>simt</b> figures are "
      "MODELED on a GPU model, not measured. <b>mlhcc</b> is a reconstruction of Xiang et al. 2023 from its "
      "description (no public code). Hover a bar for its value.</p>\n";
  html += p.html;
  html += "<footer><h2>Provenance</h2><ul>\n";
  for (const std::string& li : p.provenance) html += li;
  html += fmt::format("</ul><p>Written by <code>{}</code> at revision {}.</p></footer>\n</body></html>\n",
                      html_escape(provenance.command_line), html_escape(provenance.git_revision));
  p.md += "## Provenance\n\n";
  for (const auto& [c, kind] : csvs)
    p.md += fmt::format("- `{}` ({}, {} rows)\n", c.path, names[static_cast<int>(kind)], c.rows.size());
  p.md += fmt::format("\nWritten by `{}` at revision {}.\n", provenance.command_line, provenance.git_revision);
  write_file_atomically(out, html);
  write_file_atomically(md, p.md);
  std::printf("Wrote %s and %s from %zu CSV file(s)\n", out.c_str(), md.c_str(), csvs.size());
  return 0;
}

BoundCommand bind_report(CLI::App& parent) {
  struct State {
    std::vector<std::string> inputs;
    std::string out = "raycoh-report.html", md;
  };
  auto s = std::make_shared<State>();
  CLI::App* cmd = parent.add_subcommand(
      "report", "one self-contained HTML page (inline SVG figures) and a Markdown summary from result CSVs");
  cmd->add_option("csv", s->inputs, "result CSVs of table, sweep, converge, quality, validate, stability, tune")
      ->required();
  cmd->add_option("--out", s->out, "the HTML page")->capture_default_str();
  cmd->add_option("--md", s->md, "the Markdown summary (default: --out with .md)");
  return {cmd, [s](const Provenance& provenance) {
            const std::string md =
                s->md.empty() ? std::filesystem::path(s->out).replace_extension(".md").string() : s->md;
            return run_report(s->inputs, s->out, md, provenance);
          }};
}

}  // namespace raycoh
