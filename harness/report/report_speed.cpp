// `raycoh report`'s speed sections: a table's (Table 1 layout) and a sweep's (Table 3 layout) ratios to noopt, the
// measured ones with their paired 95% intervals and a fastest method named only where the intervals say so
// (records/speed_interval.h), figures from report_figures.cpp.
#include <fmt/format.h>

#include <map>
#include <string>
#include <vector>

#include "core/params.h"
#include "harness/report/report_parts.h"
#include "records/speed_interval.h"

namespace raycoh::report_detail {

namespace {

std::string ratio(double v, double base) { return fmt::format("{:.2f}x", base > 0 ? v / base : 0.0); }

// A method's trace / end-to-end ratios to noopt: measured ones with their paired intervals, modeled ones alone.
std::string speed_cells(const std::map<std::string, Accumulated>& t, const std::string& m, bool modeled) {
  const Accumulated& a = t.at(m);
  const Accumulated& base = t.at("noopt");
  if (modeled)
    return ratio(a.speed(true, false), base.speed(true, false)) +
           (m == "primary" ? "" : " / " + ratio(a.speed(true, true), base.speed(true, true)));
  if (m == "noopt") return "1.00x / 1.00x";
  return ratio_text(measured_ratio(base, a, false)) +
         (m == "primary" ? "" : " / " + ratio_text(measured_ratio(base, a, true)));
}

// One scene's fastest end to end: modeled, the highest modeled speed; measured, top_of_ranking over its intervals.
std::string top(const Experiment& e, const std::string& scene, const ResultKey& tl) {
  const auto& t = e.sums(scene, tl);
  std::vector<std::string> methods;
  for (const std::string& m : e.methods)
    if (m != "primary" && t.count(m)) methods.push_back(m);
  if (!e.modeled(tl)) return measured_top(t, methods);
  const std::string best = fastest_modeled(t, methods);
  return fmt::format("{} ({})", best, ratio(t.at(best).speed(true, true), t.at("noopt").speed(true, true)));
}

}  // namespace

namespace {

// Rows run under a profiler or sanitizer are no timings: the section says how many it left out, and why.
bool note_not_timings(Page& p, const Experiment& e, const std::string& path) {
  if (e.not_timings == 0) return false;
  const std::string note =
      fmt::format("{}: {} row(s) run under {} left out: a profiler's or sanitizer's times are not timings.", path,
                  e.not_timings, join(std::vector<std::string>(e.run_under.begin(), e.run_under.end()), ", "));
  p.md += note + "\n\n";
  p.html += "<p>" + html_escape(note) + "</p>\n";
  return e.tracers.empty();
}

}  // namespace

void add_table(Page& p, const ResultCsv& c) {
  const Experiment e = read_experiment(c);
  add_hw_counters(p, c, e);
  if (note_not_timings(p, e, c.path)) return;
  p.html += fmt::format("<h2>Table 1 layout: {}</h2>\n", html_escape(c.path));
  p.md += fmt::format("## Table 1 layout: {}\n\n{}\n\n", c.path, footer_of(e));
  for (const ResultKey& key : e.tracers) {
    const std::string tl = e.label(key);
    const bool modeled = e.modeled(key);
    const std::string kind = modeled ? "MODELED GPU (not measured)" : "measured";
    p.html += fmt::format("<h3>{} — {}</h3>\n<div class=\"figs\">\n", html_escape(tl), kind);
    p.html += table_figure(e, key, false, tl + ": trace only, " + (modeled ? "modeled" : "measured"));
    p.html += table_figure(e, key, true, tl + ": end to end (generation + keys + sort + permute + trace)");
    p.html += "</div>\n";
    // Markdown: methods down, scenes across, trace and end-to-end ratios to noopt.
    p.md += fmt::format("### {} ({}): speed / noopt, trace only / end to end\n\n| method |", tl, kind);
    std::string rule = "|---|";
    for (const std::string& s : e.scenes) p.md += " " + s + " |", rule += "---:|";
    p.md += "\n" + rule + "\n";
    for (const std::string& m : e.methods) {
      p.md += "| " + m + " |";
      for (const std::string& s : e.scenes) {
        const auto& t = e.sums(s, key);
        p.md += t.count(m) ? " " + speed_cells(t, m, modeled) + " |" : " — |";
      }
      p.md += "\n";
    }
    std::string line;
    for (const std::string& s : e.scenes) line += fmt::format("{} {}: {}", line.empty() ? "" : ";", s, top(e, s, key));
    p.md += fmt::format("\nFastest end to end{}:{}\n\n", modeled ? "" : " (ratio to noopt [95% interval])", line);
    p.html += fmt::format("<p class=\"win\">Fastest end to end ({}):{}</p>\n", modeled ? "modeled" : "measured",
                          html_escape(line));
  }
}

void add_sweep(Page& p, const ResultCsv& c) {
  const Experiment e = read_experiment(c);
  add_hw_counters(p, c, e);
  if (note_not_timings(p, e, c.path)) return;
  p.html += fmt::format("<h2>Table 3 layout: {}</h2>\n<div class=\"figs\">\n", html_escape(c.path));
  p.md += fmt::format("## Table 3 layout: {}\n\n{}\n\n", c.path, footer_of(e));
  for (const std::string& scene : e.scenes)
    for (const ResultKey& key : e.tracers) p.html += sweep_figure(e, scene, key);
  p.html += "</div>\n";
}

}  // namespace raycoh::report_detail
