// `raycoh report`'s speed sections: a table's (Table 1 layout) and a sweep's (Table 3 layout) ratios to noopt, the
// measured ones with their paired 95% intervals and a fastest method named only where the intervals say so
// (records/speed_interval.h), figures from report_figures.cpp.
#include <fmt/format.h>

#include <map>
#include <string>
#include <vector>

#include "core/params.h"
#include "harness/report_parts.h"
#include "records/speed_interval.h"

namespace raycoh::report_detail {

namespace {

std::string ratio(double v, double base) { return fmt::format("{:.2f}x", base > 0 ? v / base : 0.0); }

// A method's trace / end-to-end ratios to noopt: measured ones with their paired intervals, modeled ones alone.
std::string speed_cells(const std::map<std::string, Sums>& t, const std::string& m, bool modeled) {
  const Sums& a = t.at(m);
  const Sums& base = t.at("noopt");
  if (modeled)
    return ratio(a.speed(true, false), base.speed(true, false)) +
           (m == "primary" ? "" : " / " + ratio(a.speed(true, true), base.speed(true, true)));
  if (m == "noopt") return "1.00x / 1.00x";
  return ratio_text(paired_ratio(base.trace_times, a.trace_times)) +
         (m == "primary" ? "" : " / " + ratio_text(paired_ratio(base.e2e_times, a.e2e_times)));
}

// One scene's fastest end to end: modeled, the highest modeled speed; measured, top_of_ranking over its intervals.
std::string top(const Experiment& e, const std::string& scene, const std::string& tl) {
  const auto& t = e.sums.at(scene).at(tl);
  if (e.modeled.at(tl)) {
    std::pair<std::string, double> best{"", 0.0};
    for (const auto& [m, a] : t)
      if (m != "primary" && a.speed(true, true) > best.second) best = {m, a.speed(true, true)};
    return fmt::format("{} ({})", best.first, ratio(best.second, t.at("noopt").speed(true, true)));
  }
  std::vector<std::pair<std::string, const FrameSeries*>> ranked;
  for (const std::string& m : e.methods)
    if (m != "primary" && t.count(m)) ranked.emplace_back(m, &t.at(m).e2e_times);
  return top_of_ranking(ranked, t.at("noopt").e2e_times);
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
  add_hw_counters(p, c);
  if (note_not_timings(p, e, c.path)) return;
  p.html += fmt::format("<h2>Table 1 layout: {}</h2>\n", html_escape(c.path));
  p.md += fmt::format("## Table 1 layout: {}\n\n{}\n\n", c.path, footer_of(e));
  for (const std::string& tl : e.tracers) {
    const bool modeled = e.modeled.at(tl);
    const std::string kind = modeled ? "MODELED GPU (not measured)" : "measured";
    p.html += fmt::format("<h3>{} — {}</h3>\n<div class=\"figs\">\n", html_escape(tl), kind);
    p.html += table_figure(e, tl, false, tl + ": trace only, " + (modeled ? "modeled" : "measured"));
    p.html += table_figure(e, tl, true, tl + ": end to end (generation + keys + sort + permute + trace)");
    p.html += "</div>\n";
    // Markdown: methods down, scenes across, trace and end-to-end ratios to noopt.
    p.md += fmt::format("### {} ({}): speed / noopt, trace only / end to end\n\n| method |", tl, kind);
    std::string rule = "|---|";
    for (const std::string& s : e.scenes) p.md += " " + s + " |", rule += "---:|";
    p.md += "\n" + rule + "\n";
    for (const std::string& m : e.methods) {
      p.md += "| " + m + " |";
      for (const std::string& s : e.scenes) {
        const auto& t = e.sums.at(s).at(tl);
        p.md += t.count(m) ? " " + speed_cells(t, m, modeled) + " |" : " — |";
      }
      p.md += "\n";
    }
    std::string line;
    for (const std::string& s : e.scenes) line += fmt::format("{} {}: {}", line.empty() ? "" : ";", s, top(e, s, tl));
    p.md += fmt::format("\nFastest end to end{}:{}\n\n", modeled ? "" : " (ratio to noopt [95% interval])", line);
    p.html += fmt::format("<p class=\"win\">Fastest end to end ({}):{}</p>\n", modeled ? "modeled" : "measured",
                          html_escape(line));
  }
}

void add_sweep(Page& p, const ResultCsv& c) {
  const Experiment e = read_experiment(c);
  add_hw_counters(p, c);
  if (note_not_timings(p, e, c.path)) return;
  p.html += fmt::format("<h2>Table 3 layout: {}</h2>\n<div class=\"figs\">\n", html_escape(c.path));
  p.md += fmt::format("## Table 3 layout: {}\n\n{}\n\n", c.path, footer_of(e));
  for (const std::string& scene : e.scenes)
    for (const std::string& tl : e.tracers) p.html += sweep_figure(e, scene, tl);
  p.html += "</div>\n";
}

}  // namespace raycoh::report_detail
