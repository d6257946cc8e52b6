// `raycoh report CSV...`: one self-contained HTML page (figures as inline SVG, images as data URIs, no scripts, no
// external files) and a Markdown summary, from the result CSVs of `table`, `sweep`, `converge` and `quality`.
//
// Figures: the paper's Table 1 layout as bars of the ratio to noopt (generators as groups and hues, encoders as
// shades of their generator's hue, axis from 0), trace only and end to end, per tracer (`simt` figures modeled,
// and labelled so); Table 3 heatmaps (tile down, K across); error against CPU time (wall clock and trace) from
// converge curves, log-log; the quality images side by side; provenance at the bottom. Colours: Okabe & Ito's
// colour-blind-safe palette, and a light-to-dark blue ramp for the heatmaps, every cell also printed as a number.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "core/durable_file.h"
#include "core/error.h"
#include "harness/command.h"
#include "records/csv.h"
#include "shading/image.h"

namespace raycoh {

namespace {

// ---------------------------------------------------------------------------------------------------------------
// Reading

struct Csv {
  std::string path;
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
  int col(const std::string& name) const {
    const auto it = std::find(columns.begin(), columns.end(), name);
    return it == columns.end() ? -1 : static_cast<int>(it - columns.begin());
  }
  bool has(const std::string& name) const { return col(name) >= 0; }
  const std::string& get(const std::vector<std::string>& row, const std::string& name) const {
    static const std::string empty;
    const int c = col(name);
    return c < 0 ? empty : row[static_cast<size_t>(c)];
  }
  double num(const std::vector<std::string>& row, const std::string& name) const {
    const std::string& s = get(row, name);
    if (s.empty()) return NAN;
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    return end && *end == '\0' ? v : NAN;
  }
};

Csv read_csv(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(fmt::format("report: cannot read {}", path));
  Csv csv;
  csv.path = path;
  std::string line;
  int number = 0;
  std::vector<std::string> fields;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    if (!csv_parse_line(line, fields)) throw Error(fmt::format("report: {} line {}: unbalanced quotes", path, number));
    if (csv.columns.empty()) {
      csv.columns = fields;
      continue;
    }
    if (fields.size() != csv.columns.size())
      throw Error(fmt::format("report: {} line {}: {} fields, the header has {}", path, number, fields.size(),
                              csv.columns.size()));
    csv.rows.push_back(fields);
  }
  if (csv.columns.empty()) throw Error(fmt::format("report: {}: empty file, no CSV header", path));
  return csv;
}

enum class Kind { Table, Sweep, Converge, ConvergeSummary, Quality, Validate, Stability };

Kind kind_of(const Csv& c) {
  if (c.has("pass") && c.has("method") && c.has("mray_s")) {
    static const std::regex cell(R"(^(ours|contiguous|tile):tile=\d+x\d+,k=\d+$)");
    size_t cells = 0, others = 0;  // a sweep: its every method but noopt a tile x K cell of ours or contiguous
    for (const auto& r : c.rows) {
      if (c.get(r, "pass") != "secondary" || c.get(r, "method") == "noopt") continue;
      ++(std::regex_match(c.get(r, "method"), cell) ? cells : others);
    }
    return cells > 0 && others == 0 ? Kind::Sweep : Kind::Table;
  }
  if (c.has("equal_time_error_ratio")) return Kind::ConvergeSummary;
  if (c.has("rel_mse") && c.has("wall_s") && c.has("frame")) return Kind::Converge;
  if (c.has("psnr") && c.has("reference_kind")) return Kind::Quality;
  if (c.has("paper_ratio") && c.has("modeled_ratio")) return Kind::Validate;
  if (c.has("case") && c.has("rate") && c.has("threshold") && c.has("status")) return Kind::Stability;
  throw Error(fmt::format(
      "report: {}: not a raycoh result CSV; valid: the CSVs of table, sweep, converge (curve or -summary), quality, "
      "validate and stability (results/README.md)",
      c.path));
}

std::string html_escape(const std::string& s) {
  std::string out;
  for (char ch : s) {
    if (ch == '&')
      out += "&amp;";
    else if (ch == '<')
      out += "&lt;";
    else if (ch == '>')
      out += "&gt;";
    else if (ch == '"')
      out += "&quot;";
    else
      out += ch;
  }
  return out;
}

std::string base64(const std::string& bytes) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t v = (uint8_t(bytes[i]) << 16) | (uint8_t(bytes[i + 1]) << 8) | uint8_t(bytes[i + 2]);
    out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], t[v & 63]};
  }
  if (i + 1 == bytes.size()) {
    const uint32_t v = uint8_t(bytes[i]) << 16;
    out += {t[v >> 18], t[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == bytes.size()) {
    const uint32_t v = (uint8_t(bytes[i]) << 16) | (uint8_t(bytes[i + 1]) << 8);
    out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], '='};
  }
  return out;
}

// ---------------------------------------------------------------------------------------------------------------
// Colours and SVG helpers

// Okabe & Ito (2008), colour-blind safe; noopt (the baseline) is grey.
const char* const kHues[] = {"#0072B2", "#E69F00", "#009E73", "#CC79A7", "#D55E00", "#56B4E9", "#F0E442"};

std::string generator_colour(const std::string& generator, const std::vector<std::string>& generators) {
  if (generator == "noopt") return "#666666";
  size_t i = 0;  // the same hue for a generator in every figure of a file, with or without the primary bound
  for (const std::string& g : generators) {
    if (g == generator) break;
    if (g != "noopt" && g != "primary") ++i;
  }
  return kHues[i % 7];
}

// The colour mixed with white: shade 0 is the colour itself, shade 1 almost white.
std::string lighten(const std::string& hex, double shade) {
  const int r = std::stoi(hex.substr(1, 2), nullptr, 16), g = std::stoi(hex.substr(3, 2), nullptr, 16),
            b = std::stoi(hex.substr(5, 2), nullptr, 16);
  auto mix = [&](int c) { return static_cast<int>(std::lround(c + (255 - c) * shade)); };
  return fmt::format("#{:02x}{:02x}{:02x}", mix(r), mix(g), mix(b));
}

// A light-to-dark blue ramp for heatmaps (t in [0, 1]).
std::string ramp(double t) {
  t = std::clamp(t, 0.0, 1.0);
  const int r = static_cast<int>(std::lround(239 + (8 - 239) * t)),
            g = static_cast<int>(std::lround(243 + (48 - 243) * t)),
            b = static_cast<int>(std::lround(255 + (107 - 255) * t));
  return fmt::format("#{:02x}{:02x}{:02x}", r, g, b);
}

std::string text(double x, double y, const std::string& s, const char* anchor = "middle", int size = 12,
                 const char* extra = "") {
  return fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"{}\" font-size=\"{}\"{}>{}</text>\n", x, y, anchor,
                     size, extra, html_escape(s));
}

// "Nice" axis ticks from 0 to at least hi.
std::vector<double> ticks(double hi) {
  const double raw = hi / 5;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double step = raw / mag < 2 ? 2 * mag : raw / mag < 5 ? 5 * mag : 10 * mag;
  std::vector<double> t;
  for (double v = 0; v < hi + step * 0.999; v += step) t.push_back(v);
  return t;
}

// ---------------------------------------------------------------------------------------------------------------
// Experiment CSVs (table, sweep): sums over frames per scene, tracer and method.

struct Sums {
  double rays = 0, trace_ms = 0, e2e_ms = 0, modeled_ms = 0, modeled_e2e_ms = 0;
  std::string generator, encoder;
  double speed(bool modeled, bool e2e) const {
    const double ms = modeled ? (e2e ? modeled_e2e_ms : modeled_ms) : (e2e ? e2e_ms : trace_ms);
    return ms > 0 ? rays / ms * 1e-3 : 0.0;
  }
};

struct Experiment {
  std::vector<std::string> scenes, tracers, methods;  // in file order
  std::map<std::string, bool> modeled;                // tracer label -> figures are the GPU model's
  std::map<std::string, std::map<std::string, std::map<std::string, Sums>>> sums;  // scene, tracer, method
  std::set<std::string> revisions, resolutions, frames, cpus, commands;
};

void add_unique(std::vector<std::string>& v, const std::string& s) {
  if (std::find(v.begin(), v.end(), s) == v.end()) v.push_back(s);
}

// "simt[preset=rtx3060]": the tracer and, for a GPU model, its preset; "cpu", "embree[mode=packet16]".
std::string tracer_label(const std::string& tracer, const std::string& params) {
  const size_t at = params.find("preset=");
  if (at != std::string::npos) return tracer + "[" + params.substr(at, params.find(',', at) - at) + "]";
  const size_t mode = params.find("mode=");
  if (mode != std::string::npos) return tracer + "[" + params.substr(mode, params.find(',', mode) - mode) + "]";
  return tracer;
}

Experiment read_experiment(const Csv& c) {
  Experiment e;
  std::map<std::string, std::set<std::string>> frames_of;
  for (const auto& r : c.rows) {
    const std::string scene = c.get(r, "scene"), tl = tracer_label(c.get(r, "tracer"), c.get(r, "tracer_params")),
                      method = c.get(r, "method");
    add_unique(e.scenes, scene);
    add_unique(e.tracers, tl);
    add_unique(e.methods, method);
    const bool modeled = !std::isnan(c.num(r, "modeled_ms"));
    e.modeled[tl] = modeled;
    Sums& s = e.sums[scene][tl][method];
    s.generator = c.get(r, "generator");
    s.encoder = c.get(r, "encoder").empty() ? "none" : c.get(r, "encoder");
    s.rays += c.num(r, "rays");
    s.trace_ms += c.num(r, "trace_ms");
    s.e2e_ms += c.num(r, "e2e_ms");
    if (modeled) {
      s.modeled_ms += c.num(r, "modeled_ms");
      s.modeled_e2e_ms += c.num(r, "modeled_e2e_ms");
    }
    e.revisions.insert(c.get(r, "git_revision"));
    e.resolutions.insert(c.get(r, "width") + "×" + c.get(r, "height"));
    frames_of[scene].insert(c.get(r, "frame"));
    e.cpus.insert(c.get(r, "cpu") + ", " + c.get(r, "threads") + " threads");
    e.commands.insert(c.get(r, "command_line"));
  }
  for (const auto& [scene, f] : frames_of) e.frames.insert(std::to_string(f.size()));
  return e;
}

std::string join_set(const std::set<std::string>& s, const char* sep = ", ") {
  std::string out;
  for (const std::string& v : s) out += (out.empty() ? "" : sep) + v;
  return out;
}

// The footer of a figure: resolution, frames and revision, then the tracers (two lines of SVG text).
std::string footer_of(const Experiment& e, const std::string& tracer = "") {
  std::string tracers;
  for (const std::string& t : e.tracers)
    if (tracer.empty() || t == tracer)
      tracers += (tracers.empty() ? "" : ", ") + t + (e.modeled.at(t) ? " (modeled)" : " (measured)");
  return fmt::format("{}, {} frame(s), tracer {}, revision {}", join_set(e.resolutions), join_set(e.frames), tracers,
                     join_set(e.revisions));
}

// The Table 1 layout as bars: scenes across, in each scene the methods grouped by generator (one hue each, a gap
// between groups), encoders as shades of the hue (none the full colour); the value is the ratio to noopt.
std::string table_figure(const Experiment& e, const std::string& tl, bool e2e, const std::string& title) {
  std::vector<std::string> generators, encoders, methods;
  for (const std::string& m : e.methods) {
    if (m == "primary" && e2e) continue;
    const Sums& s = e.sums.at(e.scenes.front()).at(tl).at(m);
    add_unique(generators, s.generator);
    add_unique(encoders, s.encoder);
  }
  // Methods in generator-major order (primary first: the coherent bound).
  for (const std::string& g : generators)
    for (const std::string& enc : encoders)
      for (const std::string& m : e.methods) {
        if (m == "primary" && e2e) continue;
        const Sums& s = e.sums.at(e.scenes.front()).at(tl).at(m);
        if (s.generator == g && s.encoder == enc) methods.push_back(m);
      }
  const bool modeled = e.modeled.at(tl);
  double hi = 1.0;
  for (const std::string& scene : e.scenes)
    for (const std::string& m : methods) {
      const auto& t = e.sums.at(scene).at(tl);
      if (!t.count(m)) continue;
      hi = std::max(hi, t.at(m).speed(modeled, e2e) / std::max(t.at("noopt").speed(modeled, e2e), 1e-30));
    }
  const std::vector<double> tk = ticks(hi * 1.05);
  const double top = tk.back();
  const double bar = 9, gap = 8, scene_gap = 30, left = 60, plot_h = 220, top_y = 40;
  const double scene_w = methods.size() * bar + (generators.size() - 1) * gap;
  const double width = left + e.scenes.size() * (scene_w + scene_gap) + 10;
  const double legend_y = top_y + plot_h + 50;
  const size_t per_row = 5;
  const double height = legend_y + 22 + 18 * ((encoders.size() + per_row - 1) / per_row) + 16;
  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0f}\" height=\"{:.0f}\" viewBox=\"0 0 {:.0f} {:.0f}\" "
      "role=\"img\" font-family=\"sans-serif\">\n<title>{}</title>\n",
      std::max(width, 700.0), height, std::max(width, 700.0), height, html_escape(title));
  svg += text(left, 18, title, "start", 14, " font-weight=\"bold\"");
  auto y_of = [&](double v) { return top_y + plot_h * (1 - v / top); };
  for (double v : tk) {
    svg += fmt::format("<line x1=\"{}\" x2=\"{:.0f}\" y1=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#ddd\"/>\n", left,
                       width - 10, y_of(v), y_of(v));
    svg += text(left - 6, y_of(v) + 4, fmt::format("{:g}", v), "end", 11);
  }
  svg += fmt::format(
      "<line x1=\"{}\" x2=\"{:.0f}\" y1=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#000\" stroke-dasharray=\"4 3\"/>\n", left,
      width - 10, y_of(1), y_of(1));
  svg += fmt::format(
      "<text transform=\"translate(16,{:.0f}) rotate(-90)\" text-anchor=\"middle\" font-size=\"12\">{} speed / "
      "noopt (axis from 0; dashed: 1)</text>\n",
      top_y + plot_h / 2, modeled ? "modeled" : "measured");
  double x = left + scene_gap / 2;
  for (const std::string& scene : e.scenes) {
    const auto& t = e.sums.at(scene).at(tl);
    const double base = std::max(t.at("noopt").speed(modeled, e2e), 1e-30);
    double bx = x;
    std::string prev;
    for (const std::string& m : methods) {
      const Sums& s = e.sums.at(e.scenes.front()).at(tl).at(m);
      if (!prev.empty() && s.generator != prev) bx += gap;
      prev = s.generator;
      if (t.count(m)) {
        const double v = t.at(m).speed(modeled, e2e) / base;
        const size_t ei = std::find(encoders.begin(), encoders.end(), s.encoder) - encoders.begin();
        const std::string fill = m == "primary" ? "#000000"
                                                : lighten(generator_colour(s.generator, generators),
                                                          0.75 * ei / std::max<size_t>(encoders.size(), 2));
        svg += fmt::format(
            "<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" fill=\"{}\" stroke=\"#333\" "
            "stroke-width=\"0.5\"><title>{} {}: {:.2f}x noopt</title></rect>\n",
            bx, y_of(v), bar - 1, y_of(0) - y_of(v), fill, html_escape(scene), html_escape(m), v);
      }
      bx += bar;
    }
    svg += text(x + scene_w / 2, top_y + plot_h + 18, scene, "middle", 12);
    x += scene_w + scene_gap;
  }
  svg += fmt::format("<line x1=\"{}\" x2=\"{:.0f}\" y1=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#000\"/>\n", left, width - 10,
                     y_of(0), y_of(0));
  // Legend: hue = generator, shade = encoder.
  double lx = left;
  svg += text(lx, legend_y, "colour = generator:", "start", 12);
  lx += 125;
  for (const std::string& g : generators) {
    const std::string fill = g == "primary" ? "#000000" : generator_colour(g, generators);
    svg += fmt::format("<rect x=\"{:.0f}\" y=\"{:.0f}\" width=\"12\" height=\"12\" fill=\"{}\"/>\n", lx, legend_y - 10,
                       fill);
    const std::string name = g == "primary" ? "primary (coherent bound)" : g;
    svg += text(lx + 16, legend_y, name, "start", 12);
    lx += 22 + 7.0 * name.size();
  }
  svg += text(left, legend_y + 22, "shade = encoder (left to right):", "start", 12);
  for (size_t i = 0; i < encoders.size(); ++i) {
    const double ex = left + 200 + (i % per_row) * 85, ey = legend_y + 22 + 18 * (i / per_row);
    svg += fmt::format(
        "<rect x=\"{:.0f}\" y=\"{:.0f}\" width=\"12\" height=\"12\" fill=\"{}\" stroke=\"#333\" "
        "stroke-width=\"0.5\"/>\n",
        ex, ey - 10, lighten("#444444", 0.75 * i / std::max<size_t>(encoders.size(), 2)));
    svg += text(ex + 16, ey, encoders[i], "start", 12);
  }
  svg += text(left, height - 6, footer_of(e, tl), "start", 10, " fill=\"#555\"");
  return svg + "</svg>\n";
}

// Table 3 as a heatmap: tile W×H down, K across, the ratio to noopt in every cell.
std::string sweep_figure(const Experiment& e, const std::string& scene, const std::string& tl) {
  static const std::regex cell(R"(^\w+:tile=(\d+)x(\d+),k=(\d+)$)");
  std::vector<std::string> tiles;
  std::vector<int> ks;
  std::map<std::pair<std::string, int>, double> value;
  const bool modeled = e.modeled.at(tl);
  const auto& t = e.sums.at(scene).at(tl);
  const double base = std::max(t.at("noopt").speed(modeled, false), 1e-30);
  double lo = 1e30, hi = 0;
  for (const std::string& m : e.methods) {
    std::smatch sm;
    if (!t.count(m) || !std::regex_match(m, sm, cell)) continue;
    const std::string tile = sm[1].str() + "×" + sm[2].str();
    const int k = std::stoi(sm[3].str());
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
  const std::string title = fmt::format("{} — {} ({})", scene, tl, modeled ? "modeled" : "measured");
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
  svg += text(10, height - 8, footer_of(e, tl), "start", 10, " fill=\"#555\"");
  return svg + "</svg>\n";
}

// ---------------------------------------------------------------------------------------------------------------
// Converge curves: error against CPU time, log-log, one line per method.

// "simt[preset=rtx3060,kernel=...]" -> "simt[preset=rtx3060,...]" (the CSV keeps every parameter).
std::string short_model(const std::string& spec) {
  const size_t comma = spec.find(',');
  return comma == std::string::npos ? spec : spec.substr(0, comma) + ",...]";
}

std::string converge_figure(const Csv& c, const std::string& clock, const std::string& metric) {
  std::map<std::string, std::vector<std::pair<double, double>>> lines;
  std::vector<std::string> methods;
  double x0 = 1e30, x1 = 0, y0 = 1e30, y1 = 0;
  std::string scene, rev, res;
  for (const auto& r : c.rows) {
    const double x = c.num(r, clock), y = c.num(r, metric);
    if (!(x > 0) || !(y > 0)) continue;
    add_unique(methods, c.get(r, "method"));
    lines[c.get(r, "method")].push_back({x, y});
    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    scene = c.get(r, "scene");
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
  const std::string what = clock == "wall_s" ? "CPU wall-clock s" : modeled ? "MODELED GPU s" : "CPU trace s";
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
  svg +=
      text(10, height - 8,
           fmt::format("{}; revision {}; {}", res, rev,
                       modeled ? "MODELED on " + short_model(c.get(c.rows.front(), "gpu_model")) : "measured CPU time"),
           "start", 10, " fill=\"#555\"");
  return svg + "</svg>\n";
}

// ---------------------------------------------------------------------------------------------------------------
// The page

struct Page {
  std::string html, md;
  std::vector<std::string> provenance;  // one <li> per CSV
};

std::string ratio(double v, double base) { return fmt::format("{:.2f}x", base > 0 ? v / base : 0.0); }

void add_table(Page& p, const Csv& c) {
  const Experiment e = read_experiment(c);
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
    std::map<std::string, std::pair<std::string, double>> best;  // scene -> fastest end to end
    for (const std::string& m : e.methods) {
      p.md += "| " + m + " |";
      for (const std::string& s : e.scenes) {
        const auto& t = e.sums.at(s).at(tl);
        if (!t.count(m)) {
          p.md += " — |";
          continue;
        }
        const Sums& a = t.at(m);
        const double b = t.at("noopt").speed(modeled, false), be = t.at("noopt").speed(modeled, true);
        p.md += " " + ratio(a.speed(modeled, false), b) +
                (m == "primary" ? "" : " / " + ratio(a.speed(modeled, true), be)) + " |";
        if (m != "primary" && a.speed(modeled, true) / be > best[s].second) best[s] = {m, a.speed(modeled, true) / be};
      }
      p.md += "\n";
    }
    p.md += "\nFastest end to end:";
    std::string line;
    for (const std::string& s : e.scenes)
      line += fmt::format("{} {} {} ({:.2f}x)", line.empty() ? "" : ";", s, best[s].first, best[s].second);
    p.md += line + "\n\n";
    p.html += fmt::format("<p class=\"win\">Fastest end to end ({}):{}</p>\n", modeled ? "modeled" : "measured",
                          html_escape(line));
  }
}

void add_sweep(Page& p, const Csv& c) {
  const Experiment e = read_experiment(c);
  p.html += fmt::format("<h2>Table 3 layout: {}</h2>\n<div class=\"figs\">\n", html_escape(c.path));
  p.md += fmt::format("## Table 3 layout: {}\n\n{}\n\n", c.path, footer_of(e));
  for (const std::string& scene : e.scenes)
    for (const std::string& tl : e.tracers) p.html += sweep_figure(e, scene, tl);
  p.html += "</div>\n";
}

void add_converge(Page& p, const Csv& c) {
  p.html += fmt::format(
      "<h2>Error against time: {}</h2>\n<p><code>converge</code> renders images on the CPU tracer (wall and trace "
      "time measured there); where the CSV has it, the same frames' MODELED time on the GPU model "
      "(<code>--gpu-model</code>) is a third clock, never added to a measured one.</p>\n<div class=\"figs\">\n",
      html_escape(c.path));
  p.html += converge_figure(c, "wall_s", "rel_mse");
  p.html += converge_figure(c, "trace_s", "rel_mse");
  if (c.has("modeled_gpu_s")) p.html += converge_figure(c, "modeled_gpu_s", "rel_mse");
  p.html += "</div>\n";
}

void add_converge_summary(Page& p, const Csv& c) {
  p.md += fmt::format(
      "## Equal-time and equal-error ratios: {}\n\n| scene | method | baseline | metric | clock | "
      "equal-time error ratio | equal-error speed-up |\n|---|---|---|---|---|---:|---:|\n",
      c.path);
  std::string rows;
  for (const auto& r : c.rows) {
    const std::string line = fmt::format(
        "| {} | {} | {} | {} | {} | {:.3f} | {:.3f} |\n", c.get(r, "scene"), c.get(r, "method"), c.get(r, "baseline"),
        c.get(r, "metric"), c.get(r, "clock"), c.num(r, "equal_time_error_ratio"), c.num(r, "equal_error_speedup"));
    p.md += line;
    rows += "<tr>";
    for (const char* col : {"scene", "method", "baseline", "metric", "clock"})
      rows += "<td>" + html_escape(c.get(r, col)) + "</td>";
    rows += fmt::format("<td>{:.3f}</td><td>{:.3f}</td></tr>\n", c.num(r, "equal_time_error_ratio"),
                        c.num(r, "equal_error_speedup"));
  }
  p.md += "\n";
  p.html += fmt::format(
      "<h2>Equal-time and equal-error ratios: {}</h2>\n<table><tr><th>scene</th><th>method</th><th>baseline</th>"
      "<th>metric</th><th>clock</th><th>equal-time error ratio (&lt;1: less error)</th><th>equal-error speed-up "
      "(&gt;1: faster)</th></tr>\n{}</table>\n",
      html_escape(c.path), rows);
}

// The error map of one image against the reference, both as shown (the 8-bit PNGs the quality command writes):
// per pixel the mean absolute difference of the three channels, times kErrorGain, on a black-red-yellow-white
// ramp (black: equal; white: a difference of 1/kErrorGain of the display range or more). Empty when the images
// cannot be decoded or differ in size.
constexpr float kErrorGain = 4.f;
std::string error_map_png(const std::string& image, const std::string& reference) {
  Rgba8Image a, b;
  std::string why;
  if (!decode_rgba8(reinterpret_cast<const unsigned char*>(image.data()), image.size(), a, why) ||
      !decode_rgba8(reinterpret_cast<const unsigned char*>(reference.data()), reference.size(), b, why) ||
      a.width != b.width || a.height != b.height)
    return "";
  Image map(a.width, a.height);
  // The display value v is stored as the linear value the PNG encoder's sRGB curve turns back into v.
  const auto linear = [](float v) { return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f); };
  for (size_t p = 0; p < map.pixels(); ++p) {
    float d = 0.f;
    for (int c = 0; c < 3; ++c) d += std::abs(float(a.rgba[4 * p + c]) - float(b.rgba[4 * p + c])) / 255.f;
    const float e = std::clamp(kErrorGain * d / 3.f, 0.f, 1.f) * 3.f;  // 0..1 red, 1..2 yellow, 2..3 white
    map.rgb[3 * p] = linear(std::min(e, 1.f));
    map.rgb[3 * p + 1] = linear(std::clamp(e - 1.f, 0.f, 1.f));
    map.rgb[3 * p + 2] = linear(std::clamp(e - 2.f, 0.f, 1.f));
  }
  return png_bytes(map, ToneMap{ToneMapKind::Clamp, 1.f, false});
}

std::string cell(double v, const char* spec);

// Bias, the hybrid rule's exposure, the reference's noise and FLIP per scene and method, from quality CSVs that
// have those columns (revision 3710ea4 on; older ones: nothing).
void add_quality_bias(Page& p, const Csv& c) {
  if (!c.has("hybrid_diffuse_share") || !c.has("bias_verdict")) return;
  const char* head =
      "| scene | method | hybrid-diffuse share | mean luma bias | ± 95% | verdict | bias px (dark / bright) | "
      "ref noise share | FLIP | HDR-FLIP |";
  p.md += fmt::format(
      "### Bias and the hybrid rule's exposure: {}\n\nhybrid-diffuse share: hit pixels whose group is hybrid and "
      "whose own class is diffuse; bias: mean of all frames against the reference (relative to its mean luma); bias "
      "px: pixels whose 95% band excludes 0 — not 5% for an unbiased method on path-traced pixels (read against "
      "noopt's; results/README.md)\n\n{}\n|---|---|---:|---:|---:|---|---:|---:|---:|---:|\n",
      c.path, head);
  std::string rows;
  for (const auto& r : c.rows) {
    const std::string cells[] = {
        cell(100 * c.num(r, "hybrid_diffuse_share"), "{:.1f}%"),
        cell(100 * c.num(r, "bias_mean_rel"), "{:+.2f}%"),
        cell(100 * c.num(r, "bias_mean_ci") / std::abs(c.num(r, "bias_mean") / c.num(r, "bias_mean_rel")), "{:.2f}%"),
        c.get(r, "bias_verdict").empty() ? "—" : c.get(r, "bias_verdict"),
        cell(100 * c.num(r, "bias_excluded"), "{:.1f}%") + " (" + cell(100 * c.num(r, "bias_excluded_dark"), "{:.1f}") +
            " / " + cell(100 * c.num(r, "bias_excluded_bright"), "{:.1f}") + ")",
        cell(100 * c.num(r, "ref_noise_share"), "{:.1f}%"),
        cell(c.num(r, "flip"), "{:.4f}"),
        cell(c.num(r, "flip_hdr"), "{:.4f}")};
    p.md += fmt::format("| {} | {} |", c.get(r, "scene"), c.get(r, "method"));
    rows += fmt::format("<tr><td>{}</td><td>{}</td>", html_escape(c.get(r, "scene")), html_escape(c.get(r, "method")));
    for (const std::string& x : cells) {
      p.md += " " + x + " |";
      rows += "<td>" + html_escape(x) + "</td>";
    }
    p.md += "\n";
    rows += "</tr>\n";
  }
  p.md += "\n";
  p.html += fmt::format(
      "<h3>Bias and the hybrid rule's exposure: {}</h3>\n<p>Hybrid-diffuse share: hit pixels whose group is hybrid "
      "and whose own class is diffuse. Bias: the mean of all frames against the reference, relative to its mean "
      "luma, with its 95% CI. Bias px: pixels whose 95% band excludes 0, which is not 5% for an unbiased method on "
      "path-traced pixels: read it against noopt's.</p>\n<table><tr><th>scene</th><th>method</th><th>hybrid-diffuse "
      "share</th><th>mean luma bias</th><th>± 95%</th><th>verdict</th><th>bias px (dark / bright)</th><th>ref noise "
      "share</th><th>FLIP</th><th>HDR-FLIP</th></tr>\n{}</table>\n",
      html_escape(c.path), rows);
}

// PSNR per scene and method (the paper's Table 2), and the images side by side when `<csv dir>/quality-images/
// <scene>-<method>.png` exist (scripts/montage.py's inputs).
void add_quality(Page& p, const Csv& c) {
  std::vector<std::string> scenes, methods;
  std::map<std::pair<std::string, std::string>, std::string> psnr;
  std::set<std::string> info;
  for (const auto& r : c.rows) {
    add_unique(scenes, c.get(r, "scene"));
    add_unique(methods, c.get(r, "method"));
    psnr[{c.get(r, "scene"), c.get(r, "method")}] = fmt::format("{:.2f}", c.num(r, "psnr"));
    info.insert(fmt::format("{}×{}, {} frames (reference {}), tracer {}, revision {}", c.get(r, "width"),
                            c.get(r, "height"), c.get(r, "frames"), c.get(r, "ref_frames"), c.get(r, "tracer"),
                            c.get(r, "git_revision")));
  }
  std::string head = "| scene |", rule = "|---|";
  for (const std::string& m : methods) head += " " + m + " |", rule += "---:|";
  p.md += fmt::format("## Image quality (PSNR, dB): {}\n\n{}\n\n{}\n{}\n", c.path, join_set(info, "; "), head, rule);
  std::string table = "<table><tr><th>scene</th>";
  for (const std::string& m : methods) table += "<th>" + html_escape(m) + "</th>";
  table += "</tr>\n";
  for (const std::string& s : scenes) {
    p.md += "| " + s + " |";
    table += "<tr><td>" + html_escape(s) + "</td>";
    for (const std::string& m : methods) {
      const auto it = psnr.find({s, m});
      p.md += " " + (it == psnr.end() ? std::string("—") : it->second) + " |";
      table += "<td>" + (it == psnr.end() ? std::string("—") : it->second) + "</td>";
    }
    p.md += "\n";
    table += "</tr>\n";
  }
  p.md += "\n";
  p.html +=
      fmt::format("<h2>Image quality: {}</h2>\n<p>PSNR in dB (higher is closer to the reference); {}</p>\n{}</table>\n",
                  html_escape(c.path), html_escape(join_set(info, "; ")), table);
  add_quality_bias(p, c);
  const std::filesystem::path dir = std::filesystem::path(c.path).parent_path() / "quality-images";
  for (const std::string& s : scenes) {
    std::string row, crops, errors, reference;
    std::vector<std::string> shown = {"reference"};
    for (const std::string& m : methods) shown.push_back(m);
    for (const std::string& m : shown) {
      const std::filesystem::path png = dir / (s + "-" + m + ".png");
      std::ifstream in(png, std::ios::binary);
      if (!in) continue;
      std::stringstream bytes;
      bytes << in.rdbuf();
      const std::string data = bytes.str();
      if (data.size() < 24 || data.compare(1, 3, "PNG") != 0) continue;  // not a PNG: left out
      const auto be32 = [&](size_t at) {
        return (uint32_t(uint8_t(data[at])) << 24) | (uint32_t(uint8_t(data[at + 1])) << 16) |
               (uint32_t(uint8_t(data[at + 2])) << 8) | uint32_t(uint8_t(data[at + 3]));
      };
      const uint32_t w = be32(16), h = be32(20);  // IHDR
      const auto it = psnr.find({s, m});
      const std::string caption = html_escape(m) + (it == psnr.end() ? "" : ", PSNR " + it->second + " dB");
      const std::string src = "data:image/png;base64," + base64(data);
      row += fmt::format("<figure><img alt=\"{} {}\" src=\"{}\"><figcaption>{}</figcaption></figure>\n", html_escape(s),
                         html_escape(m), src, caption);
      // The centre third of the image, 3x: the same pixels of every method side by side.
      crops += fmt::format(
          "<figure><div class=\"crop\" style=\"aspect-ratio:{}/{}\"><img alt=\"{} {} crop\" src=\"{}\"></div>"
          "<figcaption>{}</figcaption></figure>\n",
          w, h, html_escape(s), html_escape(m), src, caption);
      if (m == "reference") {
        reference = data;
      } else if (const std::string map = reference.empty() ? "" : error_map_png(data, reference); !map.empty()) {
        errors += fmt::format(
            "<figure><img alt=\"{} {} error map\" src=\"data:image/png;base64,{}\"><figcaption>{}</figcaption>"
            "</figure>\n",
            html_escape(s), html_escape(m), base64(map), html_escape(m));
      }
    }
    if (!errors.empty())
      crops += fmt::format(
          "</div>\n<p class=\"note\">Error maps: |image − reference| as displayed, mean of the three channels, "
          "×{:g} (black: equal; red, yellow, white: larger; white is a difference of {:.0f}% of the display range "
          "or more). Blocks, seams and fireflies show here before they show in a PSNR:</p>\n<div class=\"imgs\">\n{}",
          kErrorGain, 100.f / kErrorGain, errors);
    if (!row.empty())
      p.html += fmt::format(
          "<h3>{}</h3>\n<div class=\"imgs\">\n{}</div>\n<p class=\"note\">The centre third, enlarged 3x (nearest "
          "pixel):</p>\n<div class=\"imgs\">\n{}</div>\n",
          html_escape(s), row, crops);
  }
}

// A number, or a dash where the CSV has none (the primary bound has no paper ratio).
std::string cell(double v, const char* spec) { return std::isnan(v) ? "—" : fmt::format(fmt::runtime(spec), v); }

void add_validate(Page& p, const Csv& c) {
  p.md += fmt::format(
      "## The GPU model beside the paper: {}\n\n| table | row | paper ratio | modeled ratio | error |\n"
      "|---|---|---:|---:|---:|\n",
      c.path);
  std::string rows;
  for (const auto& r : c.rows) {
    const std::string paper = cell(c.num(r, "paper_ratio"), "{:.2f}"),
                      model = cell(c.num(r, "modeled_ratio"), "{:.2f}"),
                      error = cell(100 * c.num(r, "ratio_error"), "{:+.0f}%");
    p.md += fmt::format("| {} | {} | {} | {} | {} |\n", c.get(r, "table"), c.get(r, "row"), paper, model, error);
    rows += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                        html_escape(c.get(r, "table")), html_escape(c.get(r, "row")), paper, model, error);
  }
  p.md += "\n";
  p.html += fmt::format(
      "<h2>The GPU model beside the paper: {}</h2>\n<p>The paper's ratios are measured on its GPU; ours are the "
      "GPU model's (modeled).</p>\n<table><tr><th>table</th><th>row</th><th>paper ratio (measured)</th><th>modeled "
      "ratio</th><th>error</th></tr>\n{}</table>\n",
      html_escape(c.path), rows);
}

// `raycoh stability`: per scene, the largest rate of each case over its batches, the threshold it is held to (a
// dash: reported only) and whether every gated case passed.
void add_stability(Page& p, const Csv& c) {
  std::vector<std::string> scenes, cases;
  std::map<std::pair<std::string, std::string>, double> worst;
  std::map<std::string, std::string> threshold;
  std::map<std::string, bool> failed;
  for (const auto& r : c.rows) {
    const std::string scene = c.get(r, "scene"), what = c.get(r, "case");
    add_unique(scenes, scene);
    add_unique(cases, what);
    double& w = worst.try_emplace({scene, what}, 0.0).first->second;
    w = std::max(w, c.num(r, "rate"));
    threshold[what] = c.get(r, "threshold").empty() ? "—" : c.get(r, "threshold");
    failed[scene] = failed[scene] || c.get(r, "status") == "FAIL";
  }
  std::string head = "| scene | status |", rule = "|---|---|", hrow = "<tr><th>scene</th><th>status</th>";
  for (const std::string& k : cases) {
    head += " " + k + " (" + threshold[k] + ") |", rule += "---:|";
    hrow += "<th>" + html_escape(k) + "<br>(" + html_escape(threshold[k]) + ")</th>";
  }
  std::string md = head + "\n" + rule + "\n", rows;
  for (const std::string& sc : scenes) {
    const std::string status = failed[sc] ? "FAIL" : "ok";
    md += "| " + sc + " | " + status + " |";
    rows += "<tr><td>" + html_escape(sc) + "</td><td>" + status + "</td>";
    for (const std::string& k : cases) {
      const auto it = worst.find({sc, k});
      const std::string v = it == worst.end() ? "—" : fmt::format("{:.2g}", it->second);
      md += " " + v + " |";
      rows += "<td>" + v + "</td>";
    }
    md += "\n";
    rows += "</tr>\n";
  }
  p.md += fmt::format("## Numerical stability: {}\n\nLargest rate over the batches; threshold in brackets.\n\n{}\n",
                      c.path, md);
  p.html += fmt::format(
      "<h2>Numerical stability: {}</h2>\n<p>Largest rate of each case over the scene's ray batches, against a "
      "double-precision reference (docs/stability.md); the threshold a case is held to in brackets (— : reported "
      "only).</p>\n<div class=\"wide\"><table>{}</tr>\n{}</table></div>\n",
      html_escape(c.path), hrow, rows);
}

std::string provenance_of(const Csv& c, const char* kind) {
  std::set<std::string> revs, cpus, started, commands;
  for (const auto& r : c.rows) {
    revs.insert(c.get(r, "git_revision"));
    cpus.insert(c.get(r, "cpu") + (c.has("threads") ? ", " + c.get(r, "threads") + " threads" : ""));
    started.insert(c.get(r, "started_utc"));
    commands.insert(c.get(r, "command_line"));
  }
  return fmt::format("<li><code>{}</code> ({}, {} rows): revision {}; {}; started {}; <code>{}</code></li>\n",
                     html_escape(c.path), kind, c.rows.size(), html_escape(join_set(revs)), html_escape(join_set(cpus)),
                     html_escape(started.empty() ? "" : *started.begin()), html_escape(join_set(commands, " ; ")));
}

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
  std::vector<std::pair<Csv, Kind>> csvs;
  for (const std::string& path : inputs) {
    Csv c = read_csv(path);
    const Kind k = kind_of(c);
    csvs.emplace_back(std::move(c), k);
  }
  Page p;
  p.md =
      "# raycoh report\n\nSpeeds are ratios to noopt (higher is faster). `simt` figures are MODELED on the GPU "
      "model (docs/simt-model.md), never measured; every other tracer's are measured on the CPU named below.\n\n";
  static const char* names[] = {"table",   "sweep",    "converge curve", "converge summary",
                                "quality", "validate", "stability"};
  // Tables first, then sweeps, quality, convergence and the model's validation, whatever the argument order.
  for (Kind k : {Kind::Table, Kind::Sweep, Kind::Quality, Kind::Converge, Kind::ConvergeSummary, Kind::Validate,
                 Kind::Stability})
    for (const auto& [c, kind] : csvs) {
      if (kind != k) continue;
      if (k == Kind::Table) add_table(p, c);
      if (k == Kind::Sweep) add_sweep(p, c);
      if (k == Kind::Quality) add_quality(p, c);
      if (k == Kind::Converge) add_converge(p, c);
      if (k == Kind::ConvergeSummary) add_converge_summary(p, c);
      if (k == Kind::Validate) add_validate(p, c);
      if (k == Kind::Stability) add_stability(p, c);
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
  cmd->add_option("csv", s->inputs, "result CSVs of table, sweep, converge, quality, validate")->required();
  cmd->add_option("--out", s->out, "the HTML page")->capture_default_str();
  cmd->add_option("--md", s->md, "the Markdown summary (default: --out with .md)");
  return {cmd, [s](const Provenance& provenance) {
            const std::string md =
                s->md.empty() ? std::filesystem::path(s->out).replace_extension(".md").string() : s->md;
            return run_report(s->inputs, s->out, md, provenance);
          }};
}

}  // namespace raycoh
