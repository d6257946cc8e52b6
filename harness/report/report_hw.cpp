// `raycoh report`'s section of measured hardware counters: the rows of a table or sweep CSV that `cuda:counters=hw`
// wrote (run_under cupti-counters: their kernels were replayed by CUPTI, so the speed sections leave them out),
// per tracer, scene and method, every hw_* column as a rays-weighted mean over the frames (records/experiment_sums.h
// Experiment::hw_results: the aggregator every section reads, with these rows kept apart from the timings).
#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "harness/report/report_parts.h"
#include "records/experiment_sums.h"
#include "records/hw_columns.h"

namespace raycoh::report_detail {

namespace {

std::string cell(const Accumulated& a, size_t i) {
  const std::optional<double> v = a.hw.value(i);
  return v ? fmt::format("{:.4g}", *v) : std::string("—");
}

}  // namespace

void add_hw_counters(Page& p, const ResultCsv& c, const Experiment& e) {
  if (!c.has("hw_inst_per_ray") || e.hw_results.empty()) return;
  const std::vector<std::string> names = hw_column_names();
  std::vector<ResultKey> tracers;  // in file order
  for (const std::string& scene : e.hw_scenes)
    for (const ResultKey& k : e.hw_results.at(scene).tracers)
      if (std::find(tracers.begin(), tracers.end(), k) == tracers.end()) tracers.push_back(k);
  p.md += fmt::format(
      "## Hardware counters, MEASURED (CUPTI range profiler; kernels replayed, so these rows have no speeds): {}\n\n",
      c.path);
  p.html += fmt::format("<h2>Hardware counters, measured (CUPTI; no speeds): {}</h2>\n", html_escape(c.path));
  std::string head = "| scene | method |", rule = "|---|---|", hhead = "<tr><th>scene</th><th>method</th>";
  for (const std::string& n : names) {
    head += " " + n.substr(3) + " |";
    rule += "---:|";
    hhead += "<th>" + html_escape(n.substr(3)) + "</th>";
  }
  for (const ResultKey& tracer : tracers) {
    const std::string label = tracer.label(true);
    p.md += fmt::format("### {}\n\n{}\n{}\n", label, head, rule);
    p.html += fmt::format("<h3>{}</h3>\n<table>\n{}</tr>\n", html_escape(label), hhead);
    for (const std::string& scene : e.hw_scenes)
      for (const std::string& method : e.hw_methods) {
        const auto& by_tracer = e.hw_results.at(scene).by_tracer;
        if (!by_tracer.count(tracer) || !by_tracer.at(tracer).count(method)) continue;
        const Accumulated& s = by_tracer.at(tracer).at(method);
        p.md += "| " + scene + " | " + method + " |";
        p.html += "<tr><td>" + html_escape(scene) + "</td><td>" + html_escape(method) + "</td>";
        for (size_t i = 0; i < names.size(); ++i) {
          p.md += " " + cell(s, i) + " |";
          p.html += "<td>" + cell(s, i) + "</td>";
        }
        p.md += "\n";
        p.html += "</tr>\n";
      }
    p.md += "\n";
    p.html += "</table>\n";
  }
}

}  // namespace raycoh::report_detail
