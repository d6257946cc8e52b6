// `raycoh report`'s sections, one per kind of result CSV: HTML (figures from report_figures.cpp) and Markdown
// tables, the quality images side by side with their error maps, and each CSV's provenance.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "harness/image/render_common.h"
#include "harness/report/report_parts.h"
#include "shading/image.h"

namespace raycoh::report_detail {

void add_converge(Page& p, const ResultCsv& c) {
  p.html += fmt::format(
      "<h2>Error against time: {}</h2>\n<p><code>converge</code> renders images on the CPU tracer (wall and trace "
      "time measured there); where the CSV has it, the same frames' MODELED time on the GPU model "
      "(<code>--gpu-model</code>) is a third clock, never added to a measured one; with <code>--device cuda</code> the "
      "frames come from the device path tracer and its GPU time (MEASURED, or SIMULATED under GPGPU-Sim) is a clock "
      "of its own.</p>\n<div class=\"figs\">\n",
      html_escape(c.path));
  p.html += converge_figure(c, "wall_s", "rel_mse");
  p.html += converge_figure(c, "trace_s", "rel_mse");
  if (c.has("modeled_gpu_s")) p.html += converge_figure(c, "modeled_gpu_s", "rel_mse");
  // converge --device cuda: the device's GPU time, MEASURED on a GPU or SIMULATED under GPGPU-Sim (its own clock).
  if (c.has("gpu_s")) p.html += converge_figure(c, "gpu_s", "rel_mse");
  p.html += "</div>\n";
}

void add_converge_summary(Page& p, const ResultCsv& c) {
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
void add_quality_bias(Page& p, const ResultCsv& c) {
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

namespace {

// A quality CSV's PSNR by scene and method, and the run facts its rows record.
struct QualityTable {
  // methods: each method, followed by "<method>-denoised" when the CSV has its denoised figures (--denoise); the
  // images are <scene>-<method>.png and <scene>-<method>-denoised.png.
  std::vector<std::string> scenes, methods;
  std::map<std::pair<std::string, std::string>, std::string> psnr;
  std::set<std::string> info;
};

QualityTable read_quality_table(const ResultCsv& c) {
  QualityTable q;
  for (const auto& r : c.rows) {
    add_unique(q.scenes, c.get(r, "scene"));
    add_unique(q.methods, c.get(r, "method"));
    q.psnr[{c.get(r, "scene"), c.get(r, "method")}] = fmt::format("{:.2f}", c.num(r, "psnr"));
    if (c.has("denoised_psnr") && !c.get(r, "denoised_psnr").empty()) {
      add_unique(q.methods, c.get(r, "method") + "-denoised");
      q.psnr[{c.get(r, "scene"), c.get(r, "method") + "-denoised"}] = fmt::format("{:.2f}", c.num(r, "denoised_psnr"));
    }
    q.info.insert(fmt::format("{}×{}, {} frames (reference {}), tracer {}, revision {}", c.get(r, "width"),
                              c.get(r, "height"), c.get(r, "frames"), c.get(r, "ref_frames"), c.get(r, "tracer"),
                              c.get(r, "git_revision")));
  }
  return q;
}

// The paper's Table 2: scenes down, methods across, a dash where a scene has no row of a method.
void add_psnr_table(Page& p, const ResultCsv& c, const QualityTable& q) {
  std::string head = "| scene |", rule = "|---|";
  for (const std::string& m : q.methods) head += " " + m + " |", rule += "---:|";
  p.md += fmt::format("## Image quality (PSNR, dB): {}\n\n{}\n\n{}\n{}\n", c.path, join_set(q.info, "; "), head, rule);
  std::string table = "<table><tr><th>scene</th>";
  for (const std::string& m : q.methods) table += "<th>" + html_escape(m) + "</th>";
  table += "</tr>\n";
  for (const std::string& s : q.scenes) {
    p.md += "| " + s + " |";
    table += "<tr><td>" + html_escape(s) + "</td>";
    for (const std::string& m : q.methods) {
      const auto it = q.psnr.find({s, m});
      p.md += " " + (it == q.psnr.end() ? std::string("—") : it->second) + " |";
      table += "<td>" + (it == q.psnr.end() ? std::string("—") : it->second) + "</td>";
    }
    p.md += "\n";
    table += "</tr>\n";
  }
  p.md += "\n";
  p.html +=
      fmt::format("<h2>Image quality: {}</h2>\n<p>PSNR in dB (higher is closer to the reference); {}</p>\n{}</table>\n",
                  html_escape(c.path), html_escape(join_set(q.info, "; ")), table);
}

// One scene's images in `dir` (the reference, then every method), their centre crops and their error maps.
void add_scene_images(Page& p, const std::filesystem::path& dir, const std::string& s, const QualityTable& q) {
  std::string row, crops, errors, reference;
  std::vector<std::string> shown = {"reference"};
  for (const std::string& m : q.methods) shown.push_back(m);
  for (const std::string& m : shown) {
    const std::filesystem::path png = dir / (safe_name(s) + "-" + safe_name(m) + ".png");  // as `quality` names it
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
    const auto it = q.psnr.find({s, m});
    const std::string caption = html_escape(m) + (it == q.psnr.end() ? "" : ", PSNR " + it->second + " dB");
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
        "or more; <code>-denoised</code>: the same render after the denoiser). Blocks, seams and fireflies show "
        "here before they show in a PSNR:</p>\n<div class=\"imgs\">\n{}",
        kErrorGain, 100.f / kErrorGain, errors);
  if (!row.empty())
    p.html += fmt::format(
        "<h3>{}</h3>\n<div class=\"imgs\">\n{}</div>\n<p class=\"note\">The centre third, enlarged 3x (nearest "
        "pixel):</p>\n<div class=\"imgs\">\n{}</div>\n",
        html_escape(s), row, crops);
}

}  // namespace

// PSNR per scene and method (the paper's Table 2), and the images side by side when `<csv dir>/quality-images/
// <scene>-<method>.png` exist (scripts/montage.py's inputs).
void add_quality(Page& p, const ResultCsv& c) {
  const QualityTable q = read_quality_table(c);
  add_psnr_table(p, c, q);
  add_quality_bias(p, c);
  const std::filesystem::path dir = std::filesystem::path(c.path).parent_path() / "quality-images";
  for (const std::string& s : q.scenes) add_scene_images(p, dir, s, q);
}

// A number, or a dash where the CSV has none (the primary bound has no paper ratio).
std::string cell(double v, const char* spec) { return std::isnan(v) ? "—" : fmt::format(fmt::runtime(spec), v); }

void add_validate(Page& p, const ResultCsv& c) {
  p.md += fmt::format(
      "## The GPU model (or a GPU) beside the paper: {}\n\n| table | row | paper ratio | our ratio | error |\n"
      "|---|---|---:|---:|---:|\n",
      c.path);
  std::string rows;
  for (const auto& r : c.rows) {
    const std::string paper = cell(c.num(r, "paper_ratio"), "{:.2f}"),
                      model = cell(std::isnan(c.num(r, "modeled_ratio")) && c.has("measured_ratio")
                                       ? c.num(r, "measured_ratio")
                                       : c.num(r, "modeled_ratio"),
                                   "{:.2f}"),
                      error = cell(100 * c.num(r, "ratio_error"), "{:+.0f}%");
    p.md += fmt::format("| {} | {} | {} | {} | {} |\n", c.get(r, "table"), c.get(r, "row"), paper, model, error);
    rows += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                        html_escape(c.get(r, "table")), html_escape(c.get(r, "row")), paper, model, error);
  }
  p.md += "\n";
  p.html += fmt::format(
      "<h2>The GPU model (or a GPU) beside the paper: {}</h2>\n<p>The paper's ratios are measured on its GPU; ours "
      "are the GPU model's (modeled) or, where the CSV's kind says so, measured.</p>\n<table><tr><th>table</th>"
      "<th>row</th><th>paper ratio (measured)</th><th>our ratio</th><th>error</th></tr>\n{}</table>\n",
      html_escape(c.path), rows);
}

// `raycoh stability`: per scene, the largest rate of each case over its batches, the threshold it is held to (a
// dash: reported only) and whether every gated case passed.
void add_stability(Page& p, const ResultCsv& c) {
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

std::string provenance_of(const ResultCsv& c, const char* kind) {
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

}  // namespace raycoh::report_detail
