// `raycoh report`'s figures as inline SVG: the paper's Table 1 layout as bars of the ratio to noopt (generators as
// groups and hues, encoders as shades of their generator's hue, axis from 0), Table 3 heatmaps (tile down, K
// across), error against time from converge curves (log-log). Colours: Okabe & Ito's colour-blind-safe palette,
// and a light-to-dark blue ramp for the heatmaps, every cell also printed as a number.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "harness/report/report_parts.h"
#include "plugins/recorded_params.h"

namespace raycoh::report_detail {

namespace {

// The preset in the gpu_model text of a converge CSV written before its gpu_preset column ("simt[preset=...,...]"),
// read through the simt tracer's own table.
std::string older_gpu_preset(const std::string& gpu_model) {
  const size_t open = gpu_model.find('['), close = gpu_model.rfind(']');
  if (open == std::string::npos || close == std::string::npos || close < open) return "";
  return recorded_tracer("simt", gpu_model.substr(open + 1, close - open - 1)).preset;
}

// "simt[preset=rtx3060]": the GPU model of a converge row (the CSV keeps every parameter in gpu_model).
std::string short_model(const ResultCsv& c, const std::vector<std::string>& row) {
  const std::string preset = c.has("gpu_preset") ? c.get(row, "gpu_preset") : older_gpu_preset(c.get(row, "gpu_model"));
  return ResultKey{"simt", preset, "", "", ""}.label();
}

}  // namespace

std::string footer_of(const Experiment& e, const ResultKey* tracer) {
  std::string tracers;
  for (const ResultKey& t : e.tracers)
    if (!tracer || t == *tracer)
      tracers += (tracers.empty() ? "" : ", ") + e.label(t) + (e.modeled(t) ? " (modeled)" : " (measured)");
  return fmt::format("{}, {} frame(s), tracer {}, revision {}", join_set(e.resolutions), join_set(e.frames), tracers,
                     join_set(e.revisions));
}

namespace {

// The methods of a Table 1 figure in generator-major order (primary first: the coherent bound), with the
// generators and encoders among them in order of appearance.
struct TableMethods {
  std::vector<std::string> generators, encoders, methods;
};

TableMethods table_methods(const Experiment& e, bool e2e) {
  TableMethods t;
  for (const std::string& m : e.methods) {
    if (m == "primary" && e2e) continue;
    const MethodColumns& s = e.method_of.at(m);
    add_unique(t.generators, s.generator);
    add_unique(t.encoders, s.encoder);
  }
  for (const std::string& g : t.generators)
    for (const std::string& enc : t.encoders)
      for (const std::string& m : e.methods) {
        if (m == "primary" && e2e) continue;
        const MethodColumns& s = e.method_of.at(m);
        if (s.generator == g && s.encoder == enc) t.methods.push_back(m);
      }
  return t;
}

// The highest ratio to noopt of any bar, at least 1.
double highest_ratio(const Experiment& e, const ResultKey& tl, bool e2e, const std::vector<std::string>& methods) {
  const bool modeled = e.modeled(tl);
  double hi = 1.0;
  for (const std::string& scene : e.scenes)
    for (const std::string& m : methods) {
      const auto& t = e.sums(scene, tl);
      if (!t.count(m)) continue;
      hi = std::max(hi, t.at(m).speed(modeled, e2e) / std::max(t.at("noopt").speed(modeled, e2e), 1e-30));
    }
  return hi;
}

// Where the parts of a Table 1 figure go.
struct TableLayout {
  double top = 0;  // the axis' highest tick
  double bar = 9, gap = 8, scene_gap = 30, left = 60, plot_h = 220, top_y = 40;
  double scene_w = 0, width = 0, legend_y = 0, height = 0;
  size_t per_row = 5;  // encoders per legend row

  TableLayout(const Experiment& e, const TableMethods& t, double axis_top) : top(axis_top) {
    scene_w = t.methods.size() * bar + (t.generators.size() - 1) * gap;
    width = left + e.scenes.size() * (scene_w + scene_gap) + 10;
    legend_y = top_y + plot_h + 50;
    height = legend_y + 22 + 18 * ((t.encoders.size() + per_row - 1) / per_row) + 16;
  }
  double y_of(double v) const { return top_y + plot_h * (1 - v / top); }
};

// The svg element, the title, the value axis' grid lines and ticks, the dashed line at 1 and the axis label.
std::string table_axes(const TableLayout& l, const std::vector<double>& tk, bool modeled, const std::string& title) {
  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0f}\" height=\"{:.0f}\" viewBox=\"0 0 {:.0f} {:.0f}\" "
      "role=\"img\" font-family=\"sans-serif\">\n<title>{}</title>\n",
      std::max(l.width, 700.0), l.height, std::max(l.width, 700.0), l.height, html_escape(title));
  svg += text(l.left, 18, title, "start", 14, " font-weight=\"bold\"");
  for (double v : tk) {
    svg += fmt::format("<line x1=\"{}\" x2=\"{:.0f}\" y1=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#ddd\"/>\n", l.left,
                       l.width - 10, l.y_of(v), l.y_of(v));
    svg += text(l.left - 6, l.y_of(v) + 4, fmt::format("{:g}", v), "end", 11);
  }
  svg += fmt::format(
      "<line x1=\"{}\" x2=\"{:.0f}\" y1=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#000\" stroke-dasharray=\"4 3\"/>\n", l.left,
      l.width - 10, l.y_of(1), l.y_of(1));
  svg += fmt::format(
      "<text transform=\"translate(16,{:.0f}) rotate(-90)\" text-anchor=\"middle\" font-size=\"12\">{} speed / "
      "noopt (axis from 0; dashed: 1)</text>\n",
      l.top_y + l.plot_h / 2, modeled ? "modeled" : "measured");
  return svg;
}

// Every scene's bars with the scene's name below them, then the axis at 0.
std::string table_bars(const Experiment& e, const ResultKey& tl, bool e2e, const TableMethods& tm,
                       const TableLayout& l) {
  const bool modeled = e.modeled(tl);
  std::string svg;
  double x = l.left + l.scene_gap / 2;
  for (const std::string& scene : e.scenes) {
    const auto& t = e.sums(scene, tl);
    const double base = std::max(t.at("noopt").speed(modeled, e2e), 1e-30);
    double bx = x;
    std::string prev;
    for (const std::string& m : tm.methods) {
      const MethodColumns& s = e.method_of.at(m);
      if (!prev.empty() && s.generator != prev) bx += l.gap;
      prev = s.generator;
      if (t.count(m)) {
        const double v = t.at(m).speed(modeled, e2e) / base;
        const size_t ei = std::find(tm.encoders.begin(), tm.encoders.end(), s.encoder) - tm.encoders.begin();
        const std::string fill = m == "primary" ? "#000000"
                                                : lighten(generator_colour(s.generator, tm.generators),
                                                          0.75 * ei / std::max<size_t>(tm.encoders.size(), 2));
        svg += fmt::format(
            "<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" fill=\"{}\" stroke=\"#333\" "
            "stroke-width=\"0.5\"><title>{} {}: {:.2f}x noopt</title></rect>\n",
            bx, l.y_of(v), l.bar - 1, l.y_of(0) - l.y_of(v), fill, html_escape(scene), html_escape(m), v);
      }
      bx += l.bar;
    }
    svg += text(x + l.scene_w / 2, l.top_y + l.plot_h + 18, scene, "middle", 12);
    x += l.scene_w + l.scene_gap;
  }
  svg += fmt::format("<line x1=\"{}\" x2=\"{:.0f}\" y1=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#000\"/>\n", l.left,
                     l.width - 10, l.y_of(0), l.y_of(0));
  return svg;
}

// Legend: hue = generator, shade = encoder.
std::string table_legend(const TableMethods& tm, const TableLayout& l) {
  std::string svg;
  double lx = l.left;
  svg += text(lx, l.legend_y, "colour = generator:", "start", 12);
  lx += 125;
  for (const std::string& g : tm.generators) {
    const std::string fill = g == "primary" ? "#000000" : generator_colour(g, tm.generators);
    svg += fmt::format("<rect x=\"{:.0f}\" y=\"{:.0f}\" width=\"12\" height=\"12\" fill=\"{}\"/>\n", lx,
                       l.legend_y - 10, fill);
    const std::string name = g == "primary" ? "primary (coherent bound)" : g;
    svg += text(lx + 16, l.legend_y, name, "start", 12);
    lx += 22 + 7.0 * name.size();
  }
  svg += text(l.left, l.legend_y + 22, "shade = encoder (left to right):", "start", 12);
  for (size_t i = 0; i < tm.encoders.size(); ++i) {
    const double ex = l.left + 200 + (i % l.per_row) * 85, ey = l.legend_y + 22 + 18 * (i / l.per_row);
    svg += fmt::format(
        "<rect x=\"{:.0f}\" y=\"{:.0f}\" width=\"12\" height=\"12\" fill=\"{}\" stroke=\"#333\" "
        "stroke-width=\"0.5\"/>\n",
        ex, ey - 10, lighten("#444444", 0.75 * i / std::max<size_t>(tm.encoders.size(), 2)));
    svg += text(ex + 16, ey, tm.encoders[i], "start", 12);
  }
  return svg;
}

}  // namespace

// The Table 1 layout as bars: scenes across, in each scene the methods grouped by generator (one hue each, a gap
// between groups), encoders as shades of the hue (none the full colour); the value is the ratio to noopt.
std::string table_figure(const Experiment& e, const ResultKey& tl, bool e2e, const std::string& title) {
  const TableMethods methods = table_methods(e, e2e);
  const std::vector<double> tk = ticks(highest_ratio(e, tl, e2e, methods.methods) * 1.05);
  const TableLayout layout(e, methods, tk.back());
  std::string svg = table_axes(layout, tk, e.modeled(tl), title);
  svg += table_bars(e, tl, e2e, methods, layout);
  svg += table_legend(methods, layout);
  svg += text(layout.left, layout.height - 6, footer_of(e, &tl), "start", 10, " fill=\"#555\"");
  return svg + "</svg>\n";
}

// Table 3 as a heatmap: tile W×H down, K across, the ratio to noopt in every cell.
std::string sweep_figure(const Experiment& e, const std::string& scene, const ResultKey& tl) {
  std::vector<std::string> tiles;
  std::vector<int> ks;
  std::map<std::pair<std::string, int>, double> value;
  const bool modeled = e.modeled(tl);
  const auto& t = e.sums(scene, tl);
  const double base = std::max(t.at("noopt").speed(modeled, false), 1e-30);
  double lo = 1e30, hi = 0;
  for (const std::string& m : e.methods) {
    if (!t.count(m)) continue;
    const auto sc = sweep_cell(m, e.method_of.at(m).generator, e.method_of.at(m).recorded);
    if (!sc) continue;
    const std::string tile = fmt::format("{}×{}", sc->tile_w, sc->tile_h);
    const int k = sc->k;
    add_unique(tiles, tile);
    if (std::find(ks.begin(), ks.end(), k) == ks.end()) ks.push_back(k);
    const double v = t.at(m).speed(modeled, false) / base;
    value[{tile, k}] = v;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  std::sort(ks.begin(), ks.end());
  const double cw = 70, ch = 28, left = 70, top = 64;
  const double width = std::max(left + cw * ks.size() + 20, 440.0), height = top + ch * tiles.size() + 40;
  const std::string title = fmt::format("{} — {} ({})", scene, e.label(tl), modeled ? "modeled" : "measured");
  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0f}\" height=\"{:.0f}\" viewBox=\"0 0 {:.0f} {:.0f}\" "
      "role=\"img\" font-family=\"sans-serif\">\n<title>{}</title>\n",
      width, height, width, height, html_escape(title));
  svg += text(10, 18, title, "start", 13, " font-weight=\"bold\"");
  svg += text(left + cw * ks.size() / 2, top - 26, "group size K", "middle", 11);
  svg += text(10, top - 8, "tile W×H", "start", 11);
  for (size_t j = 0; j < ks.size(); ++j) svg += text(left + cw * (j + 0.5), top - 8, std::to_string(ks[j]));
  for (size_t i = 0; i < tiles.size(); ++i) {
    svg += text(left - 8, top + ch * (i + 0.65), tiles[i], "end");
    for (size_t j = 0; j < ks.size(); ++j) {
      const auto it = value.find({tiles[i], ks[j]});
      const double x = left + cw * j, y = top + ch * i;
      if (it == value.end()) {
        svg += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"#fff\" stroke=\"#ccc\"/>\n", x, y,
                           cw, ch);
        svg += text(x + cw / 2, y + ch * 0.65, "—", "middle", 12, " fill=\"#888\"");
        continue;
      }
      const double f = hi > lo ? (it->second - lo) / (hi - lo) : 0.5;
      svg += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"{}\" stroke=\"#fff\"/>\n", x, y, cw,
                         ch, ramp(f));
      svg += text(x + cw / 2, y + ch * 0.65, fmt::format("{:.2f}x", it->second), "middle", 12,
                  f > 0.55 ? " fill=\"#fff\"" : " fill=\"#000\"");
    }
  }
  svg += text(10, height - 22, fmt::format("speed / noopt, trace only; darker = faster ({:.2f}x to {:.2f}x)", lo, hi),
              "start", 10, " fill=\"#555\"");
  svg += text(10, height - 8, footer_of(e, &tl), "start", 10, " fill=\"#555\"");
  return svg + "</svg>\n";
}

std::string converge_figure(const ResultCsv& c, const std::string& clock, const std::string& metric) {
  std::map<std::string, std::vector<std::pair<double, double>>> lines;
  std::vector<std::string> methods;
  double x0 = 1e30, x1 = 0, y0 = 1e30, y1 = 0;
  std::string scene, rev, res, device;
  for (const auto& r : c.rows) {
    const double x = c.num(r, clock), y = c.num(r, metric);
    if (!(x > 0) || !(y > 0)) continue;
    add_unique(methods, c.get(r, "method"));
    lines[c.get(r, "method")].push_back({x, y});
    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    scene = c.get(r, "scene");
    if (clock == "gpu_s") device = c.get(r, "gpu_clock") + " on " + c.get(r, "device");  // converge --device cuda
    rev = c.get(r, "git_revision");
    res = c.get(r, "width") + "×" + c.get(r, "height") + ", tracer " + c.get(r, "tracer");
  }
  if (methods.empty()) return "";
  const double left = 70, top = 36, w = 380, h = 220, width = left + w + 150, height = top + h + 64;
  const double lx0 = std::floor(std::log10(x0)), lx1 = std::ceil(std::log10(x1)), ly0 = std::floor(std::log10(y0)),
               ly1 = std::ceil(std::log10(y1));
  auto X = [&](double v) { return left + w * (std::log10(v) - lx0) / std::max(lx1 - lx0, 1.0); };
  auto Y = [&](double v) { return top + h * (1 - (std::log10(v) - ly0) / std::max(ly1 - ly0, 1.0)); };
  const bool modeled = clock == "modeled_gpu_s";
  // The device's GPU time (gpu_s): labelled MEASURED or SIMULATED as its rows' gpu_clock says.
  const bool simulated = device.starts_with("simulated");
  const std::string what = clock == "wall_s"  ? "CPU wall-clock s"
                           : modeled          ? "MODELED GPU s"
                           : clock == "gpu_s" ? (simulated ? "SIMULATED GPU s" : "MEASURED GPU s")
                                              : "CPU trace s";
  const std::string title = fmt::format("{}: {} against {}", scene, metric, what);
  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0f}\" height=\"{:.0f}\" viewBox=\"0 0 {:.0f} {:.0f}\" "
      "role=\"img\" font-family=\"sans-serif\">\n<title>{}</title>\n",
      width, height, width, height, html_escape(title));
  svg += text(10, 18, title, "start", 13, " font-weight=\"bold\"");
  for (double p = lx0; p <= lx1; ++p) {
    svg += fmt::format("<line x1=\"{:.1f}\" x2=\"{:.1f}\" y1=\"{}\" y2=\"{}\" stroke=\"#ddd\"/>\n", X(std::pow(10, p)),
                       X(std::pow(10, p)), top, top + h);
    svg += text(X(std::pow(10, p)), top + h + 16, fmt::format("{:g}", std::pow(10, p)), "middle", 11);
  }
  for (double p = ly0; p <= ly1; ++p) {
    svg += fmt::format("<line x1=\"{}\" x2=\"{}\" y1=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#ddd\"/>\n", left, left + w,
                       Y(std::pow(10, p)), Y(std::pow(10, p)));
    svg += text(left - 6, Y(std::pow(10, p)) + 4, fmt::format("{:g}", std::pow(10, p)), "end", 11);
  }
  svg += text(left + w / 2, top + h + 34, what + " (log scale)", "middle", 12);
  svg += fmt::format(
      "<text transform=\"translate(16,{:.0f}) rotate(-90)\" text-anchor=\"middle\" font-size=\"12\">{} (log "
      "scale)</text>\n",
      top + h / 2, metric);
  for (size_t i = 0; i < methods.size(); ++i) {
    const std::string colour = methods[i] == "noopt" ? "#666666" : kHues[i % 7];
    const char* dash = i % 2 ? " stroke-dasharray=\"6 3\"" : "";
    std::string pts;
    const auto& l = lines[methods[i]];
    const size_t step = std::max<size_t>(1, l.size() / 400);  // at most ~400 points per line
    for (size_t k = 0; k < l.size(); k += step) pts += fmt::format("{:.1f},{:.1f} ", X(l[k].first), Y(l[k].second));
    svg +=
        fmt::format("<polyline points=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"2\"{}/>\n", pts, colour, dash);
    svg += fmt::format("<line x1=\"{}\" x2=\"{}\" y1=\"{}\" y2=\"{}\" stroke=\"{}\" stroke-width=\"2\"{}/>\n",
                       left + w + 14, left + w + 40, top + 10 + 18 * i, top + 10 + 18 * i, colour, dash);
    svg += text(left + w + 46, top + 14 + 18 * i, methods[i], "start", 12);
  }
  svg += text(10, height - 8,
              fmt::format("{}; revision {}; {}", res, rev,
                          modeled            ? "MODELED on " + short_model(c, c.rows.front())
                          : clock == "gpu_s" ? "device path tracer, CUDA events, " + device
                                             : "measured CPU time"),
              "start", 10, " fill=\"#555\"");
  return svg + "</svg>\n";
}

}  // namespace raycoh::report_detail
