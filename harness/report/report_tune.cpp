// The report's tune section: per scene, speed against error for every setting whose error was measured, the Pareto
// front drawn, the budget's bound, the recommendation and the paper's default marked; then the decision in words.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "harness/report/report_parts.h"

namespace raycoh::report_detail {

namespace {

struct Point {
  double x = 0, y = 0;  // speedup, error-axis ratio
  bool meets = false, front = false, recommended = false, paper = false;
  std::string label;
};

std::string axis_of(const std::string& budget) {
  return budget.find("ds8=") != std::string::npos ? "ds8" : budget.find("rel=") != std::string::npos ? "rel" : "flip";
}

double bound_of(const std::string& budget, const std::string& axis) {
  const size_t at = budget.find(axis + "=");
  return at == std::string::npos ? NAN : std::atof(budget.c_str() + at + axis.size() + 1);
}

std::string marker(const Point& p, double X, double Y) {
  const std::string fill = p.meets ? "#009E73" : "#bbbbbb";
  std::string s = fmt::format(
      "<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"4\" fill=\"{}\" stroke=\"#333\" stroke-width=\"0.5\"><title>{}: "
      "{:.2f}x, {:.3f}</title></circle>\n",
      X, Y, fill, html_escape(p.label), p.x, p.y);
  if (p.recommended)
    s += fmt::format(
        "<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"9\" fill=\"none\" stroke=\"#D55E00\" "
        "stroke-width=\"2\"/>\n",
        X, Y);
  if (p.paper)
    s += fmt::format(
        "<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"14\" height=\"14\" fill=\"none\" stroke=\"#0072B2\" "
        "stroke-width=\"2\"/>\n",
        X - 7, Y - 7);
  return s;
}

std::string tune_figure(const std::string& scene, const std::vector<Point>& pts, const std::string& axis, double bound,
                        const std::string& footer) {
  double x0 = 1e30, x1 = 0, y0 = 1e30, y1 = 0;
  for (const Point& p : pts)
    x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  if (std::isfinite(bound)) y0 = std::min(y0, bound), y1 = std::max(y1, bound);
  x0 = std::min(x0, 1.0), x1 = std::max(x1, 1.0), y0 = std::min(y0, 1.0);
  const double padx = 0.05 * std::max(x1 - x0, 0.1), pady = 0.05 * std::max(y1 - y0, 0.1);
  x0 -= padx, x1 += padx, y0 -= pady, y1 += pady;
  const double left = 60, top = 36, w = 420, h = 240, width = left + w + 190, height = top + h + 60;
  auto X = [&](double v) { return left + w * (v - x0) / (x1 - x0); };
  auto Y = [&](double v) { return top + h * (1 - (v - y0) / (y1 - y0)); };
  const std::string title = fmt::format("{}: speed against {} error (ratios to noopt)", scene, axis);
  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0f}\" height=\"{:.0f}\" viewBox=\"0 0 {:.0f} {:.0f}\" "
      "role=\"img\" font-family=\"sans-serif\">\n<title>{}</title>\n",
      width, height, width, height, html_escape(title));
  svg += text(10, 18, title, "start", 13, " font-weight=\"bold\"");
  svg += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#999\"/>\n", left, top,
                     w, h);
  svg +=
      fmt::format("<line x1=\"{:.1f}\" x2=\"{:.1f}\" y1=\"{}\" y2=\"{}\" stroke=\"#999\" stroke-dasharray=\"4 3\"/>\n",
                  X(1), X(1), top, top + h);
  if (std::isfinite(bound))
    svg += fmt::format(
               "<line x1=\"{}\" x2=\"{}\" y1=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#D55E00\" stroke-dasharray=\"6 3\"/>\n",
               left, left + w, Y(bound), Y(bound)) +
           text(left + w - 4, Y(bound) - 4, fmt::format("budget {}", bound), "end", 10, " fill=\"#D55E00\"");
  std::vector<Point> front;
  for (const Point& p : pts)
    if (p.front) front.push_back(p);
  std::sort(front.begin(), front.end(), [](const Point& a, const Point& b) { return a.x < b.x; });
  std::string line;
  for (const Point& p : front) line += fmt::format("{:.1f},{:.1f} ", X(p.x), Y(p.y));
  svg += fmt::format("<polyline points=\"{}\" fill=\"none\" stroke=\"#333\" stroke-width=\"1.5\"/>\n", line);
  for (const Point& p : pts) svg += marker(p, X(p.x), Y(p.y));
  svg += text(left, top + h + 16, fmt::format("{:.2f}", x0), "start", 11) +
         text(left + w, top + h + 16, fmt::format("{:.2f}", x1), "end", 11) +
         text(left + w / 2, top + h + 30, "speed ÷ noopt's", "middle", 12) +
         text(left - 6, top + 10, fmt::format("{:.2f}", y1), "end", 11) +
         text(left - 6, top + h, fmt::format("{:.2f}", y0), "end", 11) +
         text(left - 6, top + h / 2, axis + " ÷ noopt", "end", 11);
  const char* keys[] = {"meets the budget", "misses it", "front (line)", "recommended (ring)", "paper's 8x8, K = 8"};
  const char* colours[] = {"#009E73", "#bbbbbb", "#333", "#D55E00", "#0072B2"};
  for (int i = 0; i < 5; ++i) {
    svg += fmt::format("<circle cx=\"{}\" cy=\"{}\" r=\"5\" fill=\"{}\"/>\n", left + w + 20, top + 10 + 18 * i,
                       colours[i]);
    svg += text(left + w + 30, top + 14 + 18 * i, keys[i], "start", 11);
  }
  svg += text(10, height - 8, footer, "start", 10, " fill=\"#555\"") + "</svg>\n";
  return svg;
}

}  // namespace

void add_tune(Page& page, const ResultCsv& c) {
  std::map<std::string, std::vector<std::vector<std::string>>> by_scene;
  for (const auto& r : c.rows) by_scene[c.get(r, "scene")].push_back(r);
  for (const auto& [scene, rows] : by_scene) {
    const auto& r0 = rows.front();
    const std::string budget = c.get(r0, "budget"), axis = axis_of(budget);
    std::vector<Point> pts;
    std::string rec = "none meets the budget", paper, miss;
    for (const auto& r : rows) {
      const std::string setting = c.get(r, "setting");
      if (c.get(r, "recommended") == "1")
        rec = fmt::format("{} at {:.2f}x noopt's speed{}", setting, c.num(r, "speedup"),
                          c.num(r, "speedup") < 1 ? " (slower than noopt: no setting within the budget pays)" : "");
      if (c.get(r, "closest_miss") == "1") miss = fmt::format("{} ({})", setting, c.get(r, "reason"));
      if (c.get(r, "paper_default") == "1")
        paper = fmt::format("{:.2f}x noopt, {}", c.num(r, "speedup"),
                            c.get(r, "meets_budget") == "1" ? "meets the budget" : "misses: " + c.get(r, "reason"));
      const double y = c.num(r, axis + "_ratio");
      if (c.get(r, "error_measured") != "1" || !std::isfinite(y)) continue;
      pts.push_back({c.num(r, "speedup"), y, c.get(r, "meets_budget") == "1", c.get(r, "front") == "1",
                     c.get(r, "recommended") == "1", c.get(r, "paper_default") == "1", setting});
    }
    const bool modeled = c.get(r0, "speed_kind") == "modeled";
    const std::string speed =
        fmt::format("{} {} speed on {}", modeled ? "MODELED" : "measured", c.get(r0, "rank"), c.get(r0, "tracer_spec"));
    const std::string footer = fmt::format(
        "{}x{}; {}; error: {} seeds x {} frames ({}); budget {}; revision {}", c.get(r0, "width"), c.get(r0, "height"),
        speed, c.get(r0, "seeds"), c.get(r0, "frames"), c.get(r0, "render_tracer"), budget, c.get(r0, "git_revision"));
    const std::string words = fmt::format(
        "Recommended: {}. Paper's default (8x8, K = 8): {}.{} {} of {} settings' errors measured ({} "
        "search).",
        rec, paper, miss.empty() ? "" : " Closest miss: " + miss + ".", pts.size(), rows.size(), c.get(r0, "search"));
    page.md += fmt::format("## Tune: {} ({})\n\n{}\n\n{}\n\n", scene, c.path, words, footer);
    page.html += fmt::format("<h2>Tune: {}</h2>\n<p>{}</p>\n{}", html_escape(scene), html_escape(words),
                             pts.empty() ? "" : tune_figure(scene, pts, axis, bound_of(budget, axis), footer));
  }
}

// `tune --confirm`: per fresh seed the call re-measured (the setting over its baseline, with its interval) and
// whether it held, then the pooled row.
void add_tune_confirm(Page& page, const ResultCsv& c) {
  page.md += fmt::format(
      "## Tune's speed call confirmed on fresh seeds: {}\n\n| scene | seed(s) | setting over baseline | search said | "
      "this seed says | held |\n|---|---|---|---|---|---|\n",
      c.path);
  std::string rows;
  for (const auto& r : c.rows) {
    const std::string ratio = c.get(r, "ratio_lo").empty() ? fmt::format("{:.2f}x", c.num(r, "ratio"))
                                                           : fmt::format("{:.2f}x [{:.2f}, {:.2f}]", c.num(r, "ratio"),
                                                                         c.num(r, "ratio_lo"), c.num(r, "ratio_hi"));
    const std::string what = c.get(r, "setting") + " over " + c.get(r, "baseline") + ": " + ratio;
    page.md += fmt::format("| {} | {} ({}) | {} | {} | {} | {} |\n", c.get(r, "scene"), c.get(r, "seeds"),
                           c.get(r, "kind"), what, c.get(r, "claim"), c.get(r, "verdict"), c.get(r, "held"));
    rows +=
        fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                    html_escape(c.get(r, "scene")), html_escape(c.get(r, "seeds")), html_escape(what),
                    html_escape(c.get(r, "claim")), html_escape(c.get(r, "verdict")), html_escape(c.get(r, "held")));
  }
  page.md += "\n";
  page.html += fmt::format(
      "<h2>Tune's speed call confirmed on fresh seeds: {}</h2>\n<table><tr><th>scene</th><th>seed(s)</th><th>setting "
      "over baseline</th><th>search said</th><th>this seed says</th><th>held</th></tr>\n{}</table>\n",
      html_escape(c.path), rows);
}

}  // namespace raycoh::report_detail
