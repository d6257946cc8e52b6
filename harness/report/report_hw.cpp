// `raycoh report`'s section of measured hardware counters: the rows of a table or sweep CSV that `cuda:counters=hw`
// wrote (run_under cupti-counters: their kernels were replayed by CUPTI, so the speed sections leave them out),
// per tracer, scene and method, every hw_* column as a rays-weighted mean over the frames.
#include <fmt/format.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "harness/report/report_parts.h"
#include "records/hw_columns.h"

namespace raycoh::report_detail {

namespace {

struct HwSums {
  std::vector<double> w, rays;
};

// tracer (with its parameters) -> scene -> method -> sums; the methods in file order.
struct HwRows {
  std::map<std::string, std::map<std::string, std::map<std::string, HwSums>>> sums;
  std::vector<std::string> tracers, scenes, methods;
};

HwRows read_hw_rows(const ResultCsv& c, const std::vector<std::string>& names) {
  HwRows h;
  for (const auto& r : c.rows) {
    if (c.get(r, "run_under") != kHwCountersRunUnder) continue;
    const std::string tracer = result_key_of(c, r).label(true);
    const std::string scene = c.get(r, "scene"), method = c.get(r, "method");
    HwSums& s = h.sums[tracer][scene][method];
    s.w.resize(names.size(), 0.0);
    s.rays.resize(names.size(), 0.0);
    const double rays = c.num(r, "rays");
    for (size_t i = 0; i < names.size(); ++i)
      if (const double v = c.num(r, names[i]); !std::isnan(v) && rays > 0) s.w[i] += v * rays, s.rays[i] += rays;
    add_unique(h.tracers, tracer);
    add_unique(h.scenes, scene);
    add_unique(h.methods, method);
  }
  return h;
}

std::string cell(const HwSums& s, size_t i) {
  return s.rays[i] > 0 ? fmt::format("{:.4g}", s.w[i] / s.rays[i]) : std::string("—");
}

}  // namespace

void add_hw_counters(Page& p, const ResultCsv& c) {
  if (!c.has("hw_inst_per_ray")) return;
  const std::vector<std::string> names = hw_column_names();
  const HwRows h = read_hw_rows(c, names);
  if (h.tracers.empty()) return;
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
  for (const std::string& tracer : h.tracers) {
    p.md += fmt::format("### {}\n\n{}\n{}\n", tracer, head, rule);
    p.html += fmt::format("<h3>{}</h3>\n<table>\n{}</tr>\n", html_escape(tracer), hhead);
    for (const std::string& scene : h.scenes)
      for (const std::string& method : h.methods) {
        const auto& by_scene = h.sums.at(tracer);
        if (!by_scene.count(scene) || !by_scene.at(scene).count(method)) continue;
        const HwSums& s = by_scene.at(scene).at(method);
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
