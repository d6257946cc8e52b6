// `raycoh quality` (the paper's Table 2 layout). Per scene: the NoOpt reference (--ref-frames frames, seed +
// kReferenceSeedOffset, from the cache of shading/reference.h or --reference), then per generator
// R = --bias-renders independent renders of --frames frames with seeds seed .. seed + R - 1. Reported per generator:
//   psnr, ssim, rmse, rel_mse, mse: the mean over the R renders of each render's metric (psnr_std: their standard
//     deviation), so that two generators are compared with less noise than one render gives;
//   bias2, variance: with m_i the MSE of render i and m the MSE of the mean of the R renders, E[m_i] = b^2 + s^2
//     and E[m] = b^2 + s^2 / R, so bias2 = (R m - mean m_i) / (R - 1) and variance = (mean m_i - m) R / (R - 1)
//     estimate the squared bias and the variance of one render (per pixel and channel, linear). The reference's
//     own residual noise is part of bias2 (the same for every generator: NoOpt's bias2 is that floor). Empty for
//     R = 1.
//   ref_noise_mse, ref_noise_rel_mse: the reference's own noise (shading/metrics.h reference_noise, from its half
//     reference; empty without one), ref_noise_share the largest of noise / figure over mse, rel_mse and the PSNR
//     MSE (a warning above kNoiseWarnShare = 10%), and mse_corr, rel_mse_corr, psnr_corr, bias2_corr the figures
//     with the noise taken out (E[error] = error against the truth + reference noise, the two being independent).
//   rel_mse_ds2/4/8: relMSE of the 2x/4x/8x box-downsampled render against the downsampled reference, mean over
//     the renders: white noise drops ~4x per step, errors correlated over blocks (tile groups) stay. rel_var and
//     rel_var_ds8: the variance part of rel_mse and rel_mse_ds8 (as variance above: bias left out), so that
//     rel_var_ds8 / rel_var measures the structure of the noise alone (1/64 for white noise).
//   bias_*: bias_test (shading/metrics.h) on the luma of all R x frames frames (they are independent): the share of
//     pixels whose 95% band excludes zero (5% expected without bias), the whole-image mean bias with its 95% CI and
//     the verdict; the map goes to --images as <scene>-<generator>-bias.png (red brighter, blue darker than the
//     reference; bright where the band excludes zero, dim where not) and -bias.exr ((d, sigma, z) per pixel).
//   flip: mean ꟻLIP (LDR, NVIDIA's flip-evaluator) of render 0's display PNG against the reference's, when the
//     flip program is found ($RAYCOH_FLIP, else .venv/bin/flip, which scripts/setup makes); empty otherwise.
// --protocol ci|paper sets resolution, frames, reference frames and the metric space at once (harness/quality.h);
// --metrics linear computes PSNR/SSIM on linear radiance (the paper's protocol) instead of the tone-mapped image.
// The console shows the Table 2 layout (one row per generator, one column per scene, PSNR) and a detailed table.
// Images of every render 0, the reference and the crops go to --images. Resume: rows already in <out>.partial
// from an interrupted run with the same settings, scene, method and git revision are kept, not rendered again.
// --shard I/N: only the shard's scene x generator units (records/shard.h); a scene none of them is of is not
// loaded, the reference comes from the cache (its entry lock lets one shard render it while the others wait), its
// image is written by the shard of the scene's first generator, and `raycoh merge` joins the shards' files.
#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <set>

#include "core/durable_file.h"
#include "core/error.h"
#include "harness/cli.h"
#include "harness/command.h"
#include "harness/progress.h"
#include "records/quality_row.h"
#include "records/record_csv.h"
#include "harness/render_common.h"
#include "shading/metrics.h"
#include "shading/reference.h"

namespace raycoh {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

void check_quality(const QualityOptions& o) {
  check_common(o.common, true);
  check_frames("--frames", o.frames);
  check_frames("--ref-frames", o.ref_frames);
  if (o.bias_renders < 1 || o.bias_renders > 256)
    throw Error(fmt::format("--bias-renders {}: must be in [1, 256]", o.bias_renders));
  if (o.scenes.empty()) throw Error("--scenes: empty list");
  for (const std::string& s : o.scenes) check_scene_spec("--scenes", s);
  if (!o.reference.empty() && o.scenes.size() != 1)
    throw Error(fmt::format("--reference {}: an explicit reference image needs exactly one scene (got {})", o.reference,
                            o.scenes.size()));
  if (!o.reference.empty() && !fs::is_regular_file(o.reference))
    throw Error(fmt::format("--reference {}: no such image file", o.reference));
  check_crops(o.crops, o.common.width, o.common.height);
  check_output_file("--out", o.out);
  if (!o.image_dir.empty()) check_output_folder("--images", o.image_dir);
  check_output_folder("--cache", o.cache_dir.empty() ? default_cache_dir() : o.cache_dir);
}

// What rows of an earlier run must hold to be this run's (records/csv.h): the settings of every head().
ResumeRule quality_rule(const QualityOptions& o, const Provenance& p) {
  std::set<std::string> methods, scenes(o.scenes.begin(), o.scenes.end());
  for (const PluginSpec& g : o.generators) methods.insert(g.text());
  ResumeRule rule;
  rule.require("scene_spec", scenes)
      .require("method", methods)
      .require("tracer_spec", {o.common.tracer.text()})
      .require("width", {std::to_string(o.common.width)})
      .require("height", {std::to_string(o.common.height)})
      .require("frames", {std::to_string(o.frames)})
      .require("ref_frames", {std::to_string(o.ref_frames)})
      .require("bias_renders", {std::to_string(o.bias_renders)})
      .require("seed", {std::to_string(o.common.seed)})
      .require("max_depth", {std::to_string(o.common.max_depth)})
      .require("rr_depth", {std::to_string(o.common.rr_depth)})
      .require("tone_map", {describe(o.common.tone_map)})
      .require("protocol", {o.common.protocol})
      .require("metrics", {metric_space_name(o.common.metrics)})
      .require("reference_kind", {o.reference.empty() ? "cache" : "file"});
  if (!o.reference.empty()) rule.require("reference", {o.reference});
  return require_provenance(rule, p);
}

double mean_of(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

// R independent renders of one generator against the reference.
struct Renders {
  std::vector<double> psnr, ssim, rmse, rel_mse, mse, metric_mse;  // per render
  std::vector<double> ds[3];                                       // per render: rel_mse of the 2x/4x/8x images
  double mse_of_mean = 0;                                          // MSE of the mean of the R renders
  double rel_mse_of_mean = 0, ds8_of_mean = 0;                     // relMSE of the mean, full and 8x downsampled
  BiasReport bias;
  double bias_excluded_ds4 = std::nan("");  // bias_test's share on the 4 x 4 box-downsampled frames
  bool has_bias = false;
  FrameStats total;
  uint64_t non_finite_pixels = 0;
};

constexpr int kDownsample[3] = {2, 4, 8};

// rel_mse of the factor x factor box-downsampled images; NaN when the image is smaller than a block.
double downsampled_rel_mse(const Image& img, const Image& ref, int factor) {
  if (img.width < factor || img.height < factor) return std::nan("");
  return rel_mse(box_downsample(img, factor), box_downsample(ref, factor));
}

// Where a generator's renders are written: render 0 and its crops, tone-mapped for display.
struct ImageSink {
  std::string dir, base;  // base: "<scene>-<generator>"
  const std::vector<Crop>& crops;
  std::string hdr_dir = "";  // non-empty: every render's linear image also goes there as r<i>.exr, for HDR-FLIP
  std::string hdr_path(int r) const { return (fs::path(hdr_dir) / fmt::format("r{}.exr", r)).string(); }
  std::string main_path() const { return (fs::path(dir) / (base + display_extension())).string(); }
  void write(const Image& img, const ToneMap& tm) const {
    write_image(img, main_path(), tm);
    for (size_t ci = 0; ci < crops.size(); ++ci)
      write_image(crop(img, crops[ci]),
                  (fs::path(dir) / fmt::format("{}-crop{}{}", base, ci, display_extension())).string(), tm);
  }
  // The bias map: signed false colour (display) and, in a build with EXR, (d, sigma, z) as float.
  void write_bias(const BiasReport& b) const {
    write_image(bias_false_colour(b.map), (fs::path(dir) / (base + "-bias" + display_extension())).string(),
                ToneMap{ToneMapKind::Clamp, 1.f, false});
    if (image_io_available()) write_image(b.map, (fs::path(dir) / (base + "-bias.exr")).string());
  }
};

Renders render_generator(const QualityOptions& o, const LoadedScene& ls, Generator& generator, const std::string& label,
                         const ReferenceImage& ref, const ToneMap& tm, const ImageSink& sink, size_t item,
                         size_t items) {
  Renders out;
  Accumulator mean_acc(o.common.width, o.common.height);
  BiasSamples samples(o.common.width, o.common.height);
  // The same test on 4 x 4 blocks (shading/metrics.h): frames' block-mean luma against the downsampled reference.
  constexpr int kBiasBlock = 4;
  const bool blocks = o.common.width >= kBiasBlock && o.common.height >= kBiasBlock;
  BiasSamples block_samples(o.common.width / kBiasBlock, o.common.height / kBiasBlock);
  Progress bar;
  const int R = o.bias_renders;
  for (int r = 0; r < R; ++r) {
    PathTracer pt(ls.scene, *ls.tracer, generator, settings_of(o.common, o.common.seed + r));
    Accumulator acc(o.common.width, o.common.height);
    for (int f = 0; f < o.frames; ++f) {
      Accumulator frame(o.common.width, o.common.height);  // this frame alone, for the bias test's spread
      out.total.add(pt.render_frame(static_cast<uint32_t>(f), frame));
      acc.merge(frame);
      const std::vector<double> luma = frame_luma(frame);
      samples.add_luma(luma);
      if (blocks) block_samples.add_luma(box_downsample_luma(luma, o.common.width, o.common.height, kBiasBlock));
      bar.update(item, items, r * o.frames + f, R * o.frames, fmt::format("{} {}", ls.scene.name, label));
    }
    out.non_finite_pixels += acc.pixels_with_non_finite();
    const Image img = acc.mean();
    const ErrorMetrics m = compare_images(img, ref.image, tm, o.common.metrics);
    out.psnr.push_back(m.psnr);
    out.ssim.push_back(m.ssim);
    out.rmse.push_back(m.rmse);
    out.rel_mse.push_back(m.rel_mse);
    out.mse.push_back(m.mse);
    out.metric_mse.push_back(std::pow(10.0, -m.psnr / 10.0) * kPsnrPeak * kPsnrPeak);
    for (int k = 0; k < 3; ++k) out.ds[k].push_back(downsampled_rel_mse(img, ref.image, kDownsample[k]));
    for (size_t p = 0; p < img.pixels(); ++p) mean_acc.add(p, img.at(p));
    if (r == 0) sink.write(img, tm);
    if (!sink.hdr_dir.empty()) write_image(img, sink.hdr_path(r));
  }
  bar.clear();
  const Image mean_image = mean_acc.mean();
  out.mse_of_mean = mse(mean_image, ref.image);
  out.rel_mse_of_mean = rel_mse(mean_image, ref.image);
  out.ds8_of_mean = downsampled_rel_mse(mean_image, ref.image, 8);
  if (samples.frames() >= 2) {
    out.bias = bias_test(samples, ref.image, ref.first_half.empty() ? nullptr : &ref.first_half);
    out.has_bias = true;
    sink.write_bias(out.bias);
    if (blocks) {
      const Image ref_blocks = box_downsample(ref.image, kBiasBlock);
      const Image half_blocks = ref.first_half.empty() ? Image() : box_downsample(ref.first_half, kBiasBlock);
      out.bias_excluded_ds4 =
          bias_test(block_samples, ref_blocks, half_blocks.empty() ? nullptr : &half_blocks).excluded_fraction;
    }
  }
  return out;
}

// The measured fields of a row (its head holds the settings and the resume key).
void fill_measurements(QualityRow& row, const Renders& m, int R, int frames, const ReferenceNoise* noise) {
  row.psnr = mean_of(m.psnr);
  row.psnr_std = std::nan("");
  if (R > 1) {
    double s2 = 0;
    for (double x : m.psnr) s2 += (x - row.psnr) * (x - row.psnr);
    row.psnr_std = std::sqrt(s2 / (R - 1));
  }
  row.ssim = mean_of(m.ssim);
  row.rmse = mean_of(m.rmse);
  row.rel_mse = mean_of(m.rel_mse);
  row.mse = mean_of(m.mse);
  row.mse_of_mean = m.mse_of_mean;
  row.bias2 = R > 1 ? (R * m.mse_of_mean - row.mse) / (R - 1) : std::nan("");
  row.variance = R > 1 ? (row.mse - m.mse_of_mean) * R / (R - 1) : std::nan("");
  const double nan = std::nan("");
  row.ref_noise_mse = noise ? noise->mse : nan;
  row.ref_noise_rel_mse = noise ? noise->rel_mse : nan;
  const NoiseCorrected corr = noise ? correct_for_noise(*noise, row.mse, row.rel_mse, mean_of(m.metric_mse))
                                    : NoiseCorrected{nan, nan, nan, nan, nan};
  row.ref_noise_share = corr.share;
  row.ref_noise_residual_share = corr.residual_share;
  row.mse_corr = corr.mse;
  row.rel_mse_corr = corr.rel_mse;
  row.psnr_corr = corr.psnr;
  row.bias2_corr = noise && R > 1 ? row.bias2 - noise->mse : nan;
  row.rel_mse_ds2 = mean_of(m.ds[0]);
  row.rel_mse_ds4 = mean_of(m.ds[1]);
  row.rel_mse_ds8 = mean_of(m.ds[2]);
  // The variance part alone (as `variance` above, on relMSE): bias, which survives downsampling too, left out.
  row.rel_var = R > 1 ? (row.rel_mse - m.rel_mse_of_mean) * R / (R - 1) : nan;
  row.rel_var_ds8 = R > 1 ? (row.rel_mse_ds8 - m.ds8_of_mean) * R / (R - 1) : nan;
  row.bias_excluded = m.has_bias ? m.bias.excluded_fraction : nan;
  row.bias_excluded_dark = m.has_bias ? m.bias.excluded_dark : nan;
  row.bias_excluded_bright = m.has_bias ? m.bias.excluded_bright : nan;
  row.bias_excluded_skew = m.has_bias ? m.bias.excluded_skew : nan;
  row.bias_excluded_ds4 = m.bias_excluded_ds4;
  row.bias_mean = m.has_bias ? m.bias.mean_bias : nan;
  row.bias_mean_ci = m.has_bias ? m.bias.mean_bias_ci : nan;
  row.bias_mean_rel = m.has_bias ? m.bias.mean_bias / m.bias.ref_mean : nan;
  row.bias_z2 = m.has_bias ? m.bias.z2 : nan;
  row.bias_verdict = m.has_bias ? (m.bias.consistent ? "consistent" : "biased") : "";
  row.non_finite_samples = m.total.non_finite;
  row.non_finite_pixels = m.non_finite_pixels;
  row.render_s = m.total.wall_s;
  row.trace_s = m.total.trace_s;
  row.gen_ms = m.total.gen_s * 1e3 / (static_cast<double>(R) * frames);
  row.rays = m.total.rays();
  row.mray_s = m.total.trace_s > 0 ? static_cast<double>(m.total.rays()) / m.total.trace_s * 1e-6 : 0.0;
  row.below_geometric = m.total.generation.below_geometric;
  row.reused_rays = m.total.generation.reused_rays;
  row.hybrid_diffuse_share = m.total.generation.rays > 0 ? static_cast<double>(m.total.hybrid_diffuse) /
                                                               static_cast<double>(m.total.generation.rays)
                                                         : nan;
}

// ꟻLIP (Andersson et al. 2020) through NVIDIA's reference implementation (PyPI flip-evaluator, installed by
// scripts/setup into .venv): $RAYCOH_FLIP, else .venv/bin/flip in the working folder; "" when neither exists.
std::string flip_program() {
  const char* env = std::getenv("RAYCOH_FLIP");
  if (env && *env) return env;
  std::error_code ec;
  const fs::path venv = fs::path(".venv") / "bin" / "flip";
  return fs::is_regular_file(venv, ec) ? fs::absolute(venv).string() : "";
}

// Single-quoted for the shell.
std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// Standard output of a flip command (stderr dropped), or nothing when it cannot start or exits non-zero.
std::optional<std::string> flip_output(const std::string& cmd) {
  FILE* pipe = ::popen((cmd + " 2>/dev/null").c_str(), "r");
  if (!pipe) return std::nullopt;
  std::string text;
  char buf[256];
  while (std::fgets(buf, sizeof buf, pipe)) text += buf;
  if (::pclose(pipe) != 0) return std::nullopt;
  return text;
}

// The number flip prints after `label`, searching text from `from`, and where the label stands (npos: absent).
std::pair<double, size_t> flip_value(const std::string& text, const std::string& label, size_t from = 0) {
  const size_t at = text.find(label, from);
  return at == std::string::npos ? std::make_pair(std::nan(""), at)
                                 : std::make_pair(std::strtod(text.c_str() + at + label.size(), nullptr), at);
}

// Mean LDR-FLIP of two display images (the PNGs written); NaN when flip fails or prints no mean.
double run_flip(const std::string& program, const std::string& ref, const std::string& test) {
  const auto text = flip_output(fmt::format("{} -r {} -t {} -v 1 -nerm", quoted(program), quoted(ref), quoted(test)));
  return text ? flip_value(*text, "Mean:").first : std::nan("");
}

// HDR-FLIP (flip's mode for EXR input) of linear renders against a linear reference, in one call of the flip
// program with its defaults: ACES tone mapper, 67 pixels per degree, and the exposure range (start, stop, count)
// that flip derives from the reference's luminance, which `exposure` reports as "start..stop/count".
struct HdrFlip {
  double mean = std::nan("");  // mean over the test images of each image's mean HDR-FLIP
  std::string exposure;
};
HdrFlip run_hdr_flip(const std::string& program, const std::string& ref, const std::vector<std::string>& tests,
                     const std::string& dir) {
  std::string cmd = fmt::format("{} -r {} -v 2 -nerm -nexm -d {} -t", quoted(program), quoted(ref), quoted(dir));
  for (const std::string& t : tests) cmd += " " + quoted(t);
  HdrFlip out;
  const auto text = flip_output(cmd);
  if (!text) return out;
  double sum = 0;
  size_t found = 0;
  for (size_t at = 0;;) {
    const auto [v, where] = flip_value(*text, "Mean:", at);
    if (where == std::string::npos) break;
    sum += v;
    ++found;
    at = where + 5;
  }
  if (found != tests.size()) return out;
  out.mean = sum / static_cast<double>(found);
  out.exposure =
      fmt::format("{:.4g}..{:.4g}/{:.0f}", flip_value(*text, "Start exposure:").first,
                  flip_value(*text, "Stop exposure:").first, flip_value(*text, "Number of exposures:").first);
  return out;
}

void print_quality(const QualityOptions& o, const std::vector<QualityRow>& rows) {
  const bool linear = o.common.metrics == MetricSpace::Linear;
  std::printf(
      "\nPSNR (dB) after %d frames, mean of %d independent render(s), against a %d-frame NoOpt reference; "
      "%dx%d, max depth %d; protocol %s; metrics on %s, peak 1\n\n| generator |",
      o.frames, o.bias_renders, o.ref_frames, o.common.width, o.common.height, o.common.max_depth,
      o.common.protocol.c_str(),
      linear ? "linear radiance (no tone map)" : ("tone map " + describe(o.common.tone_map)).c_str());
  for (size_t si = 0; si < o.scenes.size(); ++si) std::printf(" %s |", rows[si * o.generators.size()].scene.c_str());
  std::printf("\n|---|");
  for (size_t i = 0; i < o.scenes.size(); ++i) std::printf("---:|");
  std::printf("\n");
  for (size_t gi = 0; gi < o.generators.size(); ++gi) {
    std::printf("| %s |", o.generators[gi].text().c_str());
    for (size_t si = 0; si < o.scenes.size(); ++si) std::printf(" %.2f |", rows[si * o.generators.size() + gi].psnr);
    std::printf("\n");
  }
  std::printf(
      "\n| scene | generator | exposure | PSNR | ± | SSIM | RMSE | relMSE | bias² | variance | NaN/Inf | "
      "render s | MRay/s |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const QualityRow& r : rows)
    std::printf("| %s | %s | %.3g | %.2f | %.2f | %.4f | %.4g | %.4g | %.3g | %.3g | %llu | %.1f | %.2f |\n",
                r.scene.c_str(), r.method.c_str(), r.exposure, r.psnr, r.psnr_std, r.ssim, r.rmse, r.rel_mse, r.bias2,
                r.variance, static_cast<unsigned long long>(r.non_finite_samples), r.render_s, r.mray_s);
  std::printf(
      "\nReference noise, structure and bias: relMSE of the 2x/4x/8x box-downsampled images (white noise drops ~4x "
      "per step, blocky noise does not); pixels whose 95%% bias band excludes zero (all, darker / brighter, after "
      "the skewness correction, on 4x4 blocks; not 5%% for an unbiased method on path-traced pixels: compare with "
      "noopt's, shading/metrics.h); mean luma bias with its 95%% CI; hybrid-diffuse share of the "
      "hit pixels; FLIP (LDR of render 0's display image; HDR of the linear renders, mean over them)\n\n| scene | "
      "generator | ref noise relMSE | share | relMSE−noise | PSNR−noise | ds2 | ds4 | ds8 | ds8/full | var ds8/full | "
      "bias px | dark / bright | skew-corr. | 4x4 blocks | mean bias | ± | rel | verdict | hybrid-diffuse | FLIP | "
      "HDR-FLIP "
      "|\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|"
      "---:|---:|\n");
  for (const QualityRow& r : rows)
    std::printf(
        "| %s | %s | %.3g | %.1f%% | %.4g | %.2f | %.4g | %.4g | %.4g | %.3f | %.3f | %.1f%% | %.1f / %.1f%% | %.1f%% "
        "| "
        "%.1f%% | %+.3g | %.2g | %+.2f%% | %s | %.1f%% | %.4f | %.4f |\n",
        r.scene.c_str(), r.method.c_str(), r.ref_noise_rel_mse, 100 * r.ref_noise_share, r.rel_mse_corr, r.psnr_corr,
        r.rel_mse_ds2, r.rel_mse_ds4, r.rel_mse_ds8, r.rel_mse_ds8 / r.rel_mse, r.rel_var_ds8 / r.rel_var,
        100 * r.bias_excluded, 100 * r.bias_excluded_dark, 100 * r.bias_excluded_bright, 100 * r.bias_excluded_skew,
        100 * r.bias_excluded_ds4, r.bias_mean, r.bias_mean_ci, 100 * r.bias_mean_rel, r.bias_verdict.c_str(),
        100 * r.hybrid_diffuse_share, r.flip, r.flip_hdr);
}

class QualityRun {
 public:
  QualityRun(const QualityOptions& o, const Provenance& p)
      : o_(o),
        provenance_(p),
        generators_(make_generators("--generators", o.generators)),
        ref_kind_(o.reference.empty() ? "cache" : "file"),
        image_dir_(o.image_dir.empty() ? stem_path(o.out) + "-images" : o.image_dir),
        flip_(image_io_available() ? flip_program() : ""),
        csv_(o.out, quality_schema(), CsvWriter::Options::resumable(o.common.force, quality_rule(o, p))) {
    std::vector<std::string> units;
    for (const std::string& spec : o.scenes)
      for (const PluginSpec& g : o.generators) units.push_back(render_unit(spec, g.text()));
    owned_ = owned_units(units, o.shard);
  }
  int run();

 private:
  QualityRow head(const std::string& spec, size_t gi) const;
  const QualityRow* finished(const std::string& spec, size_t gi) const;
  void run_scene(size_t si);
  void run_generator(const LoadedScene& ls, const ReferenceImage& ref, const ReferenceNoise* noise, const ToneMap& tm,
                     size_t si, size_t gi);
  bool owns(size_t si, size_t gi) const { return owned_[si * o_.generators.size() + gi]; }

  const QualityOptions& o_;
  const Provenance& provenance_;
  std::vector<std::unique_ptr<Generator>> generators_;
  std::string ref_kind_, image_dir_, flip_;
  RecordCsv<QualityRow> csv_;
  std::vector<QualityRow> rows_;  // scene x generator order, for the console
  std::vector<bool> owned_;       // --shard: the scene x generator units this shard renders
  std::string fingerprint_;       // of the scene being rendered
};

// The settings of a row, its resume key among them.
QualityRow QualityRun::head(const std::string& spec, size_t gi) const {
  QualityRow r;
  r.scene_spec = spec;
  r.method = o_.generators[gi].text();
  r.tracer_spec = o_.common.tracer.text();
  r.width = o_.common.width;
  r.height = o_.common.height;
  r.frames = o_.frames;
  r.ref_frames = o_.ref_frames;
  r.bias_renders = o_.bias_renders;
  r.seed = o_.common.seed;
  r.max_depth = o_.common.max_depth;
  r.rr_depth = o_.common.rr_depth;
  r.tone_map = describe(o_.common.tone_map);
  r.reference_kind = ref_kind_;
  r.protocol = o_.common.protocol;
  r.metrics = metric_space_name(o_.common.metrics);
  r.provenance = provenance_;
  r.provenance.device = device_of(o_.common.tracer);
  return r;
}

const QualityRow* QualityRun::finished(const std::string& spec, size_t gi) const {
  const std::string key = resume_key(quality_schema(), head(spec, gi));
  for (const QualityRow& row : csv_.resumed())
    if (resume_key(quality_schema(), row) == key && !(ref_kind_ == "file" && row.reference != o_.reference))
      return &row;
  return nullptr;
}

void QualityRun::run_generator(const LoadedScene& ls, const ReferenceImage& ref, const ReferenceNoise* noise,
                               const ToneMap& tm, size_t si, size_t gi) {
  const std::string label = o_.generators[gi].text();
  ImageSink sink{image_dir_, fmt::format("{}-{}", safe_name(ls.scene.name), safe_name(label)), o_.crops};
  // HDR-FLIP's inputs: the linear renders and reference as EXR in a folder of their own, removed afterwards.
  const bool hdr_flip = !flip_.empty() && image_io_available();
  if (hdr_flip) {
    sink.hdr_dir = (fs::temp_directory_path() / fmt::format("raycoh-flip-{}-{}", ::getpid(), sink.base)).string();
    fs::create_directories(sink.hdr_dir);
  }
  const Renders m = render_generator(o_, ls, *generators_[gi], label, ref, tm, sink, si * o_.generators.size() + gi,
                                     o_.scenes.size() * o_.generators.size());
  QualityRow row = head(o_.scenes[si], gi);
  row.scene = ls.scene.name;
  row.scene_triangles = ls.scene.triangle_count();
  row.scene_fingerprint = fingerprint_;
  row.generator = o_.generators[gi].name;
  row.generator_params = generators_[gi]->params();
  row.tracer = o_.common.tracer.name;
  row.tracer_params = ls.tracer->params();
  if (ref_kind_ != "file") row.ref_seed = o_.common.seed + kReferenceSeedOffset;
  row.exposure = tm.exposure;
  row.reference = ref.path;
  row.ref_non_finite_samples = ref.non_finite;
  fill_measurements(row, m, o_.bias_renders, o_.frames, noise);
  row.flip = flip_.empty()
                 ? std::nan("")
                 : run_flip(flip_, ImageSink{image_dir_, safe_name(ls.scene.name) + "-reference", {}}.main_path(),
                            sink.main_path());
  row.flip_hdr = std::nan("");
  if (hdr_flip) {
    const std::string ref_exr = (fs::path(sink.hdr_dir) / "reference.exr").string();
    write_image(ref.image, ref_exr);
    std::vector<std::string> tests;
    for (int r = 0; r < o_.bias_renders; ++r) tests.push_back(sink.hdr_path(r));
    const HdrFlip f = run_hdr_flip(flip_, ref_exr, tests, sink.hdr_dir);
    row.flip_hdr = f.mean;
    row.flip_hdr_exposure = f.exposure;
    std::error_code ec;
    fs::remove_all(sink.hdr_dir, ec);
  }
  csv_.write(row);
  warn_reference_noise(label, row.ref_noise_share);
  rows_.push_back(std::move(row));
  if (m.total.non_finite > 0)
    std::fprintf(stderr, "    warning: %s: %llu NaN/Inf frame samples were left out (counted, not added)\n",
                 label.c_str(), static_cast<unsigned long long>(m.total.non_finite));
}

void QualityRun::run_scene(size_t si) {
  const std::string& spec = o_.scenes[si];
  bool all_done = true, any = false;
  for (size_t gi = 0; gi < o_.generators.size(); ++gi)
    if (owns(si, gi)) {
      any = true;
      all_done = all_done && finished(spec, gi) != nullptr;
    }
  if (!any) return;  // a shard that owns none of the scene's units does not load it
  if (all_done) {
    std::fprintf(stderr, "[%zu/%zu] %s: finished in the interrupted run, skipped\n", si + 1, o_.scenes.size(),
                 spec.c_str());
    for (size_t gi = 0; gi < o_.generators.size(); ++gi)
      if (owns(si, gi)) rows_.push_back(*finished(spec, gi));
    return;
  }
  std::fprintf(stderr, "[%zu/%zu] ", si + 1, o_.scenes.size());
  auto ls = load(spec, o_.common.tracer);
  const ReferenceImage ref = obtain_reference(*ls, spec, o_.common, o_.ref_frames, o_.cache_dir, o_.reference);
  // One display mapping per scene, from the reference, for every generator's metrics and images.
  const ToneMap tm = resolved(o_.common.tone_map, ref.image);
  fingerprint_ = scene_fingerprint(spec);
  if (owns(si, 0)) ImageSink{image_dir_, safe_name(ls->scene.name) + "-reference", o_.crops}.write(ref.image, tm);
  const std::optional<ReferenceNoise> noise = noise_of_reference(ref, tm, o_.common.metrics);
  for (size_t gi = 0; gi < o_.generators.size(); ++gi) {
    if (!owns(si, gi)) continue;
    if (const QualityRow* row = finished(spec, gi))
      rows_.push_back(*row);
    else
      run_generator(*ls, ref, noise ? &*noise : nullptr, tm, si, gi);
  }
}

int QualityRun::run() {
  size_t reusable = 0;
  for (size_t si = 0; si < o_.scenes.size(); ++si)
    for (size_t gi = 0; gi < o_.generators.size(); ++gi) reusable += owns(si, gi) && finished(o_.scenes[si], gi);
  if (flip_.empty())
    std::fprintf(stderr,
                 "FLIP: not available (no $RAYCOH_FLIP or .venv/bin/flip; scripts/setup installs flip-evaluator), "
                 "the flip column stays empty\n");
  if (reusable > 0)
    std::fprintf(stderr, "resuming: %zu rows already measured in %s\n", reusable, csv_.partial_path().c_str());
  const auto t_start = Clock::now();
  try {
    for (size_t si = 0; si < o_.scenes.size(); ++si) run_scene(si);
  } catch (const Error& e) {
    csv_.rethrow_keeping_rows(e);
  }
  csv_.finish();
  if (!o_.shard.whole()) {
    std::printf(
        "Wrote shard %s of the run to %s (%zu rows, %s); the console tables need every shard: join the "
        "shards' files with raycoh merge\n",
        o_.shard.text().c_str(), o_.out.c_str(), rows_.size(), provenance_.git_revision.c_str());
    return 0;
  }
  print_quality(o_, rows_);
  std::printf("\nWrote %s and images in %s/ in %.1f s (%s, %d threads)\n", o_.out.c_str(), image_dir_.c_str(),
              std::chrono::duration<double>(Clock::now() - t_start).count(), provenance_.git_revision.c_str(),
              provenance_.threads);
  return 0;
}

}  // namespace

int run_quality(const QualityOptions& o, const Provenance& provenance) {
  check_quality(o);
  return QualityRun(o, provenance).run();
}

BoundCommand bind_quality(CLI::App& parent) {
  struct State {
    QualityOptions o;
    RenderText text;
    ProtocolText protocol;
    std::string scenes, generators, shard = "0/1";
  };
  auto s = std::make_shared<State>();
  s->scenes = join(s->o.scenes, ",");
  s->generators = join_specs(s->o.generators);
  CLI::App* cmd = parent.add_subcommand("quality", "image error of each generator against a NoOpt reference (Table 2)");
  cmd->add_option("--scenes", s->scenes, "comma-separated scenes")->capture_default_str();
  cmd->add_option("--generators", s->generators, "comma-separated generators")->capture_default_str();
  cmd->add_option("--frames", s->o.frames, "frames per render")->capture_default_str();
  cmd->add_option("--ref-frames", s->o.ref_frames, "NoOpt frames of the reference")->capture_default_str();
  cmd->add_option("--bias-renders", s->o.bias_renders, "independent renders per generator")->capture_default_str();
  cmd->add_option("--cache", s->o.cache_dir, "reference cache folder (default $RAYCOH_CACHE or results/cache)");
  cmd->add_option("--reference", s->o.reference, "use this .exr/.pfm as the reference (one scene)");
  cmd->add_option("--out", s->o.out, "CSV file to write")->capture_default_str();
  cmd->add_option("--images", s->o.image_dir, "folder for renders and crops (default <out stem>-images)");
  cmd->add_option("--crop", s->text.crops, "x,y,w,h hotspot region written per render (repeatable)");
  cmd->add_option("--shard", s->shard,
                  "I/N: render only shard I (0-based) of N of the scene x generator units; join with raycoh merge")
      ->capture_default_str();
  bind_render_common(cmd, s->o.common, s->text);
  bind_protocol(cmd, s->protocol, true);
  return {cmd, [s, cmd](const Provenance& provenance) {
            resolve_render_common(s->o.common, s->text);
            s->o.shard = parse_shard("--shard", s->shard);
            resolve_protocol(cmd, s->protocol, s->o.common, &s->o.frames, "--frames", &s->o.ref_frames, "--ref-frames");
            adopt_reference_frames(cmd, s->o.reference, &s->o.ref_frames);
            s->o.scenes = split_scenes("--scenes", s->scenes);
            s->o.generators = split_nonempty("--generators", s->generators);
            s->o.crops = parse_crops(s->text.crops);
            return run_quality(s->o, provenance);
          }};
}

}  // namespace raycoh
