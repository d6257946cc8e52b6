// `render`, `quality`, `converge` and `compare` (DESIGN.md section 5; CSV columns in results/README.md).
//
// render    one scene, one generator, N frames (frames 0..N-1, seed --seed) through shading/path_tracer.h;
//           writes the mean image (.exr float, .png tone-mapped, .pfm) and the --crop regions beside it.
// quality   per scene: the NoOpt reference (--ref-frames frames, seed + kReferenceSeedOffset, from the cache of
//           shading/reference.h or --reference), then per generator R = --bias-renders independent renders of
//           --frames frames with seeds seed .. seed + R - 1. Reported per generator:
//             psnr, ssim, rmse, rel_mse, mse: the mean over the R renders of each render's metric (psnr_std: their
//               standard deviation), so that two generators are compared with less noise than one render gives;
//             bias2, variance: with m_i the MSE of render i and m the MSE of the mean of the R renders,
//               E[m_i] = b^2 + s^2 and E[m] = b^2 + s^2 / R, so bias2 = (R m - mean m_i) / (R - 1) and
//               variance = (mean m_i - m) R / (R - 1) estimate the squared bias and the variance of one render
//               (per pixel and channel, linear). The reference's own residual noise is part of bias2 (it is the
//               same for every generator: NoOpt's bias2 is that floor). Empty for R = 1.
//           The console shows the paper's Table 2 layout (one row per generator, one column per scene, PSNR)
//           and a detailed table. Images of every render 0, the reference and the crops go to --images.
//           Resume: rows already in <out>.partial from an interrupted run with the same settings, scene, method
//           and git revision are kept and not rendered again.
// converge  per generator, frames are rendered round-robin (one frame of each in turn, so that load changes on
//           the machine hit all of them alike) until each has rendered --time seconds of frames (wall clock of
//           the frames themselves; the error evaluation after each frame is not counted). One CSV row per
//           generator and frame: cumulative wall and trace time and the error of the running mean against the
//           reference. Ratios against the first generator (the baseline), on relMSE, for both clocks:
//             equal-time error ratio  e_g(T) / e_base(T) at T = the shorter of the two curves' last times
//                                     (< 1: the generator is more accurate in the same time);
//             equal-error speedup     t_base(E) / t_g(E) with E = the larger of the two final errors, the
//                                     error both reach (> 1: the generator reaches it sooner).
//           Curves are read by interpolating linearly in (log time, log error) between frames (error_at_time,
//           time_to_error): Monte Carlo error falls as a power of time, which this reads exactly. Written to
//           <out stem>-summary.csv.
// compare   every metric of shading/metrics.h for two image files.
//
// A progress bar is drawn on stderr only when stderr is a terminal, so CI logs stay quiet.
#include "harness/quality.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>

#include "core/error.h"
#include "bvh/bvh_build.h"
#include "tracers/tracer.h"
#include "generators/generator.h"
#include "harness/csv.h"
#include "harness/progress.h"
#include "shading/metrics.h"
#include "shading/path_tracer.h"
#include "shading/reference.h"

namespace raycoh {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The reference renders with seeds far from the test renders' seed .. seed + 255, so they are independent.
constexpr uint32_t kReferenceSeedOffset = 1000;
constexpr int kMaxFrames = 1 << 20;

std::string num(double v) { return std::isnan(v) ? std::string() : fmt::format("{:.6g}", v); }

std::string safe_name(const std::string& text) {
  std::string out;
  for (char c : text) out += std::isalnum(static_cast<unsigned char>(c)) || c == '-' ? c : '_';
  return out;
}

RenderSettings settings_of(const RenderCommon& c, uint32_t seed) {
  RenderSettings s;
  s.width = c.width;
  s.height = c.height;
  s.seed = seed;
  s.max_depth = c.max_depth;
  s.rr_depth = c.rr_depth;
  return s;
}

void check_frames(const char* option, int frames) {
  if (frames < 1 || frames > kMaxFrames)
    throw Error(fmt::format("{} {}: must be in [1, {}]", option, frames, kMaxFrames));
}

void check_exposure(const ToneMap& tm) {
  if (!tm.auto_exposure && (!(tm.exposure > 0.f) || !(tm.exposure <= 1e6f)))
    throw Error(fmt::format("--exposure {}: must be in (0, 1e6] (or auto)", tm.exposure));
}

void check_common(const RenderCommon& c, bool needs_ssim) {
  if (c.width < 1 || c.width > 16384 || c.height < 1 || c.height > 16384)
    throw Error(fmt::format("--res {}x{}: width and height must be in [1, 16384]", c.width, c.height));
  if (needs_ssim && (c.width < kSsimWindow || c.height < kSsimWindow))
    throw Error(fmt::format("--res {}x{}: image-quality runs need at least {}x{} pixels (the SSIM window)", c.width,
                            c.height, kSsimWindow, kSsimWindow));
  if (c.max_depth < 1 || c.max_depth > 64) throw Error(fmt::format("--max-depth {}: must be in [1, 64]", c.max_depth));
  if (c.rr_depth < 1 || c.rr_depth > 64) throw Error(fmt::format("--rr-depth {}: must be in [1, 64]", c.rr_depth));
  check_exposure(c.tone_map);
  std::vector<std::string> names;
  for (const TracerInfo& t : tracer_infos()) names.push_back(t.name);
  if (std::find(names.begin(), names.end(), c.tracer.name) == names.end())
    throw Error(fmt::format("--tracer {}: unknown tracer; valid tracers: {}", c.tracer.text(), join(names)));
}

void check_crops(const std::vector<Crop>& crops, int width, int height) {
  for (const Crop& c : crops) check_crop("--crop", c, width, height);
}

// Generators made up front, so that a bad name or parameter fails before anything is rendered.
std::vector<std::unique_ptr<Generator>> make_generators(const std::string& option,
                                                        const std::vector<PluginSpec>& specs) {
  if (specs.empty()) throw Error(option + ": empty list");
  std::vector<std::unique_ptr<Generator>> out;
  std::vector<std::string> labels;
  for (const PluginSpec& s : specs) {
    if (std::find(labels.begin(), labels.end(), s.text()) != labels.end())
      throw Error(fmt::format("{}: '{}' is listed twice", option, s.text()));
    labels.push_back(s.text());
    out.push_back(make_generator(s));
  }
  return out;
}

// A scene with its BVH and tracer, which keeps references to both (so it never moves).
struct LoadedScene {
  Scene scene;
  Bvh bvh;
  std::unique_ptr<Tracer> tracer;
  LoadedScene(const std::string& spec, const PluginSpec& tracer_spec)
      : scene(load_scene(spec)), bvh(build_bvh(scene)), tracer(make_tracer(tracer_spec, scene, bvh)) {}
  LoadedScene(const LoadedScene&) = delete;
  LoadedScene& operator=(const LoadedScene&) = delete;
};

std::unique_ptr<LoadedScene> load(const std::string& spec, const PluginSpec& tracer) {
  const auto t0 = Clock::now();
  auto ls = std::make_unique<LoadedScene>(spec, tracer);
  std::string lights = fmt::format("{} emissive triangles", ls->scene.emissive_tris.size());
  if (ls->scene.env.enabled) lights += " + sky and sun";
  std::fprintf(stderr, "%s: %zu triangles, %s; loaded and BVH built in %.2f s\n", ls->scene.name.c_str(),
               ls->scene.triangle_count(), lights.c_str(), seconds_since(t0));
  return ls;
}

Image read_image_for(const std::string& option, const std::string& path) {
  try {
    return read_image(path);
  } catch (const Error& e) {
    throw Error(fmt::format("{}: {}", option, e.what()));
  }
}

struct ReferenceImage {
  Image image;
  std::string path;
  std::string kind;  // "cache" (read from the cache), "rendered" (rendered now into the cache), "file"
  uint64_t non_finite = 0;
};

ReferenceImage obtain_reference(const LoadedScene& ls, const std::string& spec, const RenderCommon& c, int ref_frames,
                                const std::string& cache_dir, const std::string& explicit_path) {
  ReferenceImage out;
  if (!explicit_path.empty()) {
    out.image = read_image_for("--reference", explicit_path);
    if (out.image.width != c.width || out.image.height != c.height)
      throw Error(fmt::format("--reference {}: the image is {}x{} but the renders are {}x{} (--res)", explicit_path,
                              out.image.width, out.image.height, c.width, c.height));
    out.path = explicit_path;
    out.kind = "file";
    return out;
  }
  ReferenceRequest req;
  req.scene_spec = spec;
  req.settings = settings_of(c, c.seed + kReferenceSeedOffset);
  req.frames = ref_frames;
  req.tracer = c.tracer;
  req.cache_dir = cache_dir;
  Progress bar;
  const std::string label = fmt::format("{} reference", ls.scene.name);
  req.progress = [&](int done, int total) { bar.update(0, 1, done - 1, total, label); };
  const Reference ref = get_reference(ls.scene, ls.bvh, req);
  bar.clear();
  if (ref.from_cache)
    std::fprintf(stderr, "    reference: %s (cached, %d frames)\n", ref.path.c_str(), ref_frames);
  else
    std::fprintf(stderr, "    reference: rendered %d frames in %.1f s -> %s\n", ref_frames, ref.render_s,
                 ref.path.c_str());
  if (ref.non_finite > 0)
    std::fprintf(stderr, "    reference: %llu NaN/Inf frame samples were left out (counted, not added)\n",
                 static_cast<unsigned long long>(ref.non_finite));
  out.image = ref.image;
  out.path = ref.path;
  out.kind = ref.from_cache ? "cache" : "rendered";
  out.non_finite = ref.non_finite;
  return out;
}

std::vector<std::string> with_provenance(std::vector<std::string> columns) {
  for (const std::string& c : provenance_columns()) columns.push_back(c);
  return columns;
}

double to_double(const std::string& s) {
  try {
    return s.empty() ? std::nan("") : std::stod(s);
  } catch (const std::exception&) {
    return std::nan("");
  }
}

std::string stem_path(const std::string& path) {
  const fs::path p(path);
  return (p.parent_path() / p.stem()).string();
}

std::string display_extension() { return image_io_available() ? ".png" : ".pfm"; }

}  // namespace

double parse_duration(const std::string& what, const std::string& text) {
  size_t end = 0;
  double v = std::nan("");
  try {
    v = std::stod(text, &end);
  } catch (const std::exception&) {
    end = 0;
  }
  const std::string unit = end > 0 ? text.substr(end) : std::string();
  double scale = 0;
  if (unit.empty() || unit == "s")
    scale = 1;
  else if (unit == "ms")
    scale = 1e-3;
  else if (unit == "m" || unit == "min")
    scale = 60;
  else if (unit == "h")
    scale = 3600;
  if (end == 0 || scale == 0)
    throw Error(fmt::format("{} '{}': expected a duration such as 60s, 1.5m, 500ms or 2h", what, text));
  v *= scale;
  if (!(v > 0) || !std::isfinite(v) || v > 1e6)
    throw Error(fmt::format("{} '{}': must be more than 0 and at most 1e6 seconds", what, text));
  return v;
}

namespace {

// Log when both values are positive (the usual case), else the value itself, so that interpolation degrades to
// linear for zero errors or times.
double lg(double v, bool use_log) { return use_log ? std::log(v) : v; }

}  // namespace

double error_at_time(const std::vector<CurvePoint>& c, double t) {
  if (c.empty() || !(t >= c.front().time) || !(t <= c.back().time)) return std::nan("");
  for (size_t k = 0; k + 1 < c.size(); ++k) {
    if (t > c[k + 1].time) continue;
    const CurvePoint& a = c[k];
    const CurvePoint& b = c[k + 1];
    if (!(b.time > a.time)) return b.error;
    const bool log_t = a.time > 0, log_e = a.error > 0 && b.error > 0;
    const double f = (lg(t, log_t) - lg(a.time, log_t)) / (lg(b.time, log_t) - lg(a.time, log_t));
    const double v = lg(a.error, log_e) + f * (lg(b.error, log_e) - lg(a.error, log_e));
    return log_e ? std::exp(v) : v;
  }
  return c.back().error;
}

double time_to_error(const std::vector<CurvePoint>& c, double e) {
  for (size_t k = 0; k < c.size(); ++k) {
    if (!(c[k].error <= e)) continue;
    if (k == 0) return c[0].time;
    const CurvePoint& a = c[k - 1];
    const CurvePoint& b = c[k];
    const bool log_t = a.time > 0, log_e = b.error > 0 && e > 0;
    double f = 1.0;
    if (lg(a.error, log_e) != lg(b.error, log_e))
      f = (lg(a.error, log_e) - lg(e, log_e)) / (lg(a.error, log_e) - lg(b.error, log_e));
    const double v = lg(a.time, log_t) + std::clamp(f, 0.0, 1.0) * (lg(b.time, log_t) - lg(a.time, log_t));
    return log_t ? std::exp(v) : v;
  }
  return std::nan("");
}

int run_render(const RenderOptions& o, const Provenance& provenance) {
  check_common(o.common, false);
  check_frames("--frames", o.frames);
  check_scene_spec("--scene", o.scene);
  check_crops(o.crops, o.common.width, o.common.height);
  check_output_image_path("--out", o.out);
  auto generator = make_generator(o.generator);

  auto ls = load(o.scene, o.common.tracer);
  PathTracer pt(ls->scene, *ls->tracer, *generator, settings_of(o.common, o.common.seed));
  Accumulator acc(o.common.width, o.common.height);
  FrameStats total;
  Progress bar;
  for (int f = 0; f < o.frames; ++f) {
    total.add(pt.render_frame(static_cast<uint32_t>(f), acc));
    bar.update(0, 1, f, o.frames, fmt::format("{} {}", ls->scene.name, o.generator.text()));
  }
  bar.clear();
  const Image image = acc.mean();
  const ToneMap tm = resolved(o.common.tone_map, image);
  write_image(image, o.out, tm);
  const std::string ext = fs::path(o.out).extension().string();
  for (size_t i = 0; i < o.crops.size(); ++i) {
    const std::string path = fmt::format("{}-crop{}{}", stem_path(o.out), i, ext);
    write_image(crop(image, o.crops[i]), path, tm);
    std::printf("crop %d,%d,%d,%d -> %s\n", o.crops[i].x, o.crops[i].y, o.crops[i].w, o.crops[i].h, path.c_str());
  }
  std::printf("%s, %s [%s], tracer %s [%s]: %d frames of %dx%d, seed %u, max depth %d\n", ls->scene.name.c_str(),
              o.generator.name.c_str(), generator->params().c_str(), o.common.tracer.name.c_str(),
              ls->tracer->params().c_str(), o.frames, o.common.width, o.common.height, o.common.seed,
              o.common.max_depth);
  std::printf("render %.2f s (trace %.2f s, generation %.3f s); %.3g rays (%.2f MRay/s traced)\n", total.wall_s,
              total.trace_s, total.gen_s, static_cast<double>(total.rays()),
              total.trace_s > 0 ? static_cast<double>(total.rays()) / total.trace_s * 1e-6 : 0.0);
  if (acc.non_finite_samples() > 0)
    std::printf("warning: %llu NaN/Inf frame samples in %llu pixels were left out of the image (counted, not added)\n",
                static_cast<unsigned long long>(acc.non_finite_samples()),
                static_cast<unsigned long long>(acc.pixels_with_non_finite()));
  else
    std::printf("NaN/Inf frame samples: 0\n");
  std::printf("wrote %s (%s)\n", o.out.c_str(), provenance.git_revision.c_str());
  return 0;
}

int run_quality(const QualityOptions& o, const Provenance& provenance) {
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
  std::vector<std::unique_ptr<Generator>> generators = make_generators("--generators", o.generators);

  const std::vector<std::string> columns = with_provenance({"scene",
                                                            "scene_spec",
                                                            "scene_triangles",
                                                            "method",
                                                            "generator",
                                                            "generator_params",
                                                            "tracer_spec",
                                                            "tracer",
                                                            "tracer_params",
                                                            "width",
                                                            "height",
                                                            "frames",
                                                            "ref_frames",
                                                            "bias_renders",
                                                            "seed",
                                                            "ref_seed",
                                                            "max_depth",
                                                            "rr_depth",
                                                            "tone_map",
                                                            "exposure",
                                                            "reference_kind",
                                                            "reference",
                                                            "psnr",
                                                            "psnr_std",
                                                            "ssim",
                                                            "rmse",
                                                            "rel_mse",
                                                            "mse",
                                                            "mse_of_mean",
                                                            "bias2",
                                                            "variance",
                                                            "non_finite_samples",
                                                            "non_finite_pixels",
                                                            "ref_non_finite_samples",
                                                            "render_s",
                                                            "trace_s",
                                                            "gen_ms",
                                                            "rays",
                                                            "mray_s",
                                                            "below_geometric",
                                                            "reused_rays"});
  const std::string tone = describe(o.common.tone_map);
  const std::string ref_kind = o.reference.empty() ? "cache" : "file";
  // What a finished row must match to be kept on resume; values of this run, by column.
  auto key_values = [&](const std::string& scene_spec, const std::string& method) {
    return std::map<std::string, std::string>{{"scene_spec", scene_spec},
                                              {"method", method},
                                              {"tracer_spec", o.common.tracer.text()},
                                              {"width", std::to_string(o.common.width)},
                                              {"height", std::to_string(o.common.height)},
                                              {"frames", std::to_string(o.frames)},
                                              {"ref_frames", std::to_string(o.ref_frames)},
                                              {"bias_renders", std::to_string(o.bias_renders)},
                                              {"seed", std::to_string(o.common.seed)},
                                              {"max_depth", std::to_string(o.common.max_depth)},
                                              {"rr_depth", std::to_string(o.common.rr_depth)},
                                              {"tone_map", tone},
                                              {"reference_kind", ref_kind},
                                              {"git_revision", provenance.git_revision}};
  };
  CsvWriter csv(o.out, columns);  // resumes the complete rows of an interrupted run with these columns
  auto matches = [&](const std::vector<std::string>& row, const std::map<std::string, std::string>& key) {
    for (const auto& [col, value] : key)
      if (row[csv.column(col)] != value) return false;
    return !(ref_kind == "file" && row[csv.column("reference")] != o.reference);
  };
  auto finished = [&](const std::string& scene_spec, const std::string& method) -> const std::vector<std::string>* {
    for (const auto& row : csv.resumed_rows())
      if (matches(row, key_values(scene_spec, method))) return &row;
    return nullptr;
  };
  size_t reusable = 0;
  for (const std::string& spec : o.scenes)
    for (const PluginSpec& g : o.generators) reusable += finished(spec, g.text()) != nullptr;
  if (reusable > 0)
    std::fprintf(stderr, "resuming: %zu rows already measured in %s\n", reusable, csv.partial_path().c_str());

  const std::string image_dir = o.image_dir.empty() ? stem_path(o.out) + "-images" : o.image_dir;
  const std::vector<std::string> prov = provenance_values(provenance);
  std::vector<std::vector<std::string>> results;  // rows in scene x generator order, for the console
  const auto t_start = Clock::now();
  try {
    for (size_t si = 0; si < o.scenes.size(); ++si) {
      const std::string& spec = o.scenes[si];
      bool all_done = true;
      for (const PluginSpec& g : o.generators) all_done = all_done && finished(spec, g.text()) != nullptr;
      if (all_done) {
        std::fprintf(stderr, "[%zu/%zu] %s: finished in the interrupted run, skipped\n", si + 1, o.scenes.size(),
                     spec.c_str());
        for (const PluginSpec& g : o.generators) results.push_back(*finished(spec, g.text()));
        continue;
      }
      std::fprintf(stderr, "[%zu/%zu] ", si + 1, o.scenes.size());
      auto ls = load(spec, o.common.tracer);
      const ReferenceImage ref = obtain_reference(*ls, spec, o.common, o.ref_frames, o.cache_dir, o.reference);
      // One display mapping per scene, from the reference, for every generator's metrics and images.
      const ToneMap tm = resolved(o.common.tone_map, ref.image);
      const std::string scene_file = safe_name(ls->scene.name);
      write_image(ref.image, (fs::path(image_dir) / (scene_file + "-reference" + display_extension())).string(), tm);
      for (size_t ci = 0; ci < o.crops.size(); ++ci)
        write_image(
            crop(ref.image, o.crops[ci]),
            (fs::path(image_dir) / fmt::format("{}-reference-crop{}{}", scene_file, ci, display_extension())).string(),
            tm);

      for (size_t gi = 0; gi < o.generators.size(); ++gi) {
        const std::string label = o.generators[gi].text();
        if (const auto* row = finished(spec, label)) {
          results.push_back(*row);
          continue;
        }
        const int R = o.bias_renders;
        std::vector<double> psnr_r, ssim_r, rmse_r, rel_r, mse_r;
        Accumulator mean_acc(o.common.width, o.common.height);
        FrameStats total;
        uint64_t non_finite_pixels = 0;
        Progress bar;
        const size_t item = si * o.generators.size() + gi, items = o.scenes.size() * o.generators.size();
        for (int r = 0; r < R; ++r) {
          PathTracer pt(ls->scene, *ls->tracer, *generators[gi], settings_of(o.common, o.common.seed + r));
          Accumulator acc(o.common.width, o.common.height);
          for (int f = 0; f < o.frames; ++f) {
            total.add(pt.render_frame(static_cast<uint32_t>(f), acc));
            bar.update(item, items, r * o.frames + f, R * o.frames, fmt::format("{} {}", ls->scene.name, label));
          }
          non_finite_pixels += acc.pixels_with_non_finite();
          const Image img = acc.mean();
          const ErrorMetrics m = compare_images(img, ref.image, tm);
          psnr_r.push_back(m.psnr);
          ssim_r.push_back(m.ssim);
          rmse_r.push_back(m.rmse);
          rel_r.push_back(m.rel_mse);
          mse_r.push_back(m.mse);
          for (size_t p = 0; p < img.pixels(); ++p) mean_acc.add(p, img.at(p));
          if (r == 0) {
            const std::string base = fmt::format("{}-{}", scene_file, safe_name(label));
            write_image(img, (fs::path(image_dir) / (base + display_extension())).string(), tm);
            for (size_t ci = 0; ci < o.crops.size(); ++ci)
              write_image(crop(img, o.crops[ci]),
                          (fs::path(image_dir) / fmt::format("{}-crop{}{}", base, ci, display_extension())).string(),
                          tm);
          }
        }
        bar.clear();
        auto mean_of = [](const std::vector<double>& v) {
          double s = 0;
          for (double x : v) s += x;
          return s / static_cast<double>(v.size());
        };
        double psnr_std = std::nan("");
        if (R > 1) {
          const double mu = mean_of(psnr_r);
          double s2 = 0;
          for (double x : psnr_r) s2 += (x - mu) * (x - mu);
          psnr_std = std::sqrt(s2 / (R - 1));
        }
        const double mse_mean_r = mean_of(mse_r);
        const double mse_of_mean = mse(mean_acc.mean(), ref.image);
        const double bias2 = R > 1 ? (R * mse_of_mean - mse_mean_r) / (R - 1) : std::nan("");
        const double variance = R > 1 ? (mse_mean_r - mse_of_mean) * R / (R - 1) : std::nan("");
        const GenerationStats& gs = total.generation;
        std::vector<std::string> row = {
            ls->scene.name,
            spec,
            std::to_string(ls->scene.triangle_count()),
            label,
            o.generators[gi].name,
            generators[gi]->params(),
            o.common.tracer.text(),
            o.common.tracer.name,
            ls->tracer->params(),
            std::to_string(o.common.width),
            std::to_string(o.common.height),
            std::to_string(o.frames),
            std::to_string(o.ref_frames),
            std::to_string(R),
            std::to_string(o.common.seed),
            ref_kind == "file" ? std::string() : std::to_string(o.common.seed + kReferenceSeedOffset),
            std::to_string(o.common.max_depth),
            std::to_string(o.common.rr_depth),
            tone,
            num(tm.exposure),
            ref_kind,
            ref.path,
            num(mean_of(psnr_r)),
            num(psnr_std),
            num(mean_of(ssim_r)),
            num(mean_of(rmse_r)),
            num(mean_of(rel_r)),
            num(mse_mean_r),
            num(mse_of_mean),
            num(bias2),
            num(variance),
            std::to_string(total.non_finite),
            std::to_string(non_finite_pixels),
            std::to_string(ref.non_finite),
            num(total.wall_s),
            num(total.trace_s),
            num(total.gen_s * 1e3 / (static_cast<double>(R) * o.frames)),
            std::to_string(total.rays()),
            num(total.trace_s > 0 ? static_cast<double>(total.rays()) / total.trace_s * 1e-6 : 0.0),
            std::to_string(gs.below_geometric),
            std::to_string(gs.reused_rays)};
        row.insert(row.end(), prov.begin(), prov.end());
        csv.write_row(row);
        results.push_back(std::move(row));
        if (total.non_finite > 0)
          std::fprintf(stderr, "    warning: %s: %llu NaN/Inf frame samples were left out (counted, not added)\n",
                       label.c_str(), static_cast<unsigned long long>(total.non_finite));
      }
    }
  } catch (const Error& e) {
    csv.discard_if_empty();
    if (csv.rows() + csv.resumed_rows().size() == 0) throw;
    throw Error(fmt::format("{} ({} rows measured so far are kept in {}; run the same command again to resume)",
                            e.what(), csv.rows() + csv.resumed_rows().size(), csv.partial_path()));
  }
  csv.finish();

  // The paper's Table 2: one row per generator, one column per scene.
  auto cell = [&](const std::vector<std::string>& row, const char* col) { return to_double(row[csv.column(col)]); };
  std::vector<std::string> scene_names;
  for (size_t si = 0; si < o.scenes.size(); ++si) scene_names.push_back(results[si * o.generators.size()][0]);
  std::printf(
      "\nPSNR (dB) after %d frames, mean of %d independent render(s), against a %d-frame NoOpt reference; "
      "%dx%d, max depth %d; tone map %s, peak 1\n\n| generator |",
      o.frames, o.bias_renders, o.ref_frames, o.common.width, o.common.height, o.common.max_depth, tone.c_str());
  for (const std::string& s : scene_names) std::printf(" %s |", s.c_str());
  std::printf("\n|---|");
  for (size_t i = 0; i < scene_names.size(); ++i) std::printf("---:|");
  std::printf("\n");
  for (size_t gi = 0; gi < o.generators.size(); ++gi) {
    std::printf("| %s |", o.generators[gi].text().c_str());
    for (size_t si = 0; si < o.scenes.size(); ++si)
      std::printf(" %.2f |", cell(results[si * o.generators.size() + gi], "psnr"));
    std::printf("\n");
  }
  std::printf(
      "\n| scene | generator | exposure | PSNR | ± | SSIM | RMSE | relMSE | bias² | variance | NaN/Inf | "
      "render s | MRay/s |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const auto& row : results)
    std::printf("| %s | %s | %.3g | %.2f | %.2f | %.4f | %.4g | %.4g | %.3g | %.3g | %s | %.1f | %.2f |\n",
                row[0].c_str(), row[csv.column("method")].c_str(), cell(row, "exposure"), cell(row, "psnr"),
                cell(row, "psnr_std"), cell(row, "ssim"), cell(row, "rmse"), cell(row, "rel_mse"), cell(row, "bias2"),
                cell(row, "variance"), row[csv.column("non_finite_samples")].c_str(), cell(row, "render_s"),
                cell(row, "mray_s"));
  std::printf("\nWrote %s and images in %s/ in %.1f s (%s, %d threads)\n", o.out.c_str(), image_dir.c_str(),
              seconds_since(t_start), provenance.git_revision.c_str(), provenance.threads);
  return 0;
}

int run_converge(const ConvergeOptions& o, const Provenance& provenance) {
  check_common(o.common, true);
  check_frames("--max-frames", o.max_frames);
  check_frames("--ref-frames", o.ref_frames);
  if (!(o.time_s > 0) || !std::isfinite(o.time_s) || o.time_s > 1e6)
    throw Error(fmt::format("--time {}: must be more than 0 and at most 1e6 seconds", o.time_s));
  check_scene_spec("--scene", o.scene);
  if (!o.reference.empty() && !fs::is_regular_file(o.reference))
    throw Error(fmt::format("--reference {}: no such image file", o.reference));
  std::vector<std::unique_ptr<Generator>> generators = make_generators("--generators", o.generators);

  auto ls = load(o.scene, o.common.tracer);
  const ReferenceImage ref = obtain_reference(*ls, o.scene, o.common, o.ref_frames, o.cache_dir, o.reference);

  const std::vector<std::string> columns = with_provenance({"scene",
                                                            "scene_spec",
                                                            "method",
                                                            "generator",
                                                            "generator_params",
                                                            "tracer",
                                                            "tracer_params",
                                                            "width",
                                                            "height",
                                                            "seed",
                                                            "ref_frames",
                                                            "max_depth",
                                                            "rr_depth",
                                                            "tone_map",
                                                            "reference",
                                                            "frame",
                                                            "wall_s",
                                                            "trace_s",
                                                            "gen_s",
                                                            "frame_wall_ms",
                                                            "frame_trace_ms",
                                                            "rays",
                                                            "rel_mse",
                                                            "mse",
                                                            "rmse",
                                                            "psnr",
                                                            "ssim",
                                                            "non_finite_samples"});
  // A convergence curve is one timed measurement: an interrupted run starts again rather than resuming.
  CsvWriter csv(o.out, columns, CsvWriter::Resume::No);
  const std::vector<std::string> prov = provenance_values(provenance);
  const ToneMap tm = resolved(o.common.tone_map, ref.image);  // from the reference, the same for every generator
  const std::string tone = describe(tm);

  struct Run {
    std::string label;
    std::unique_ptr<PathTracer> pt;
    Accumulator acc;
    FrameStats total;
    int frames = 0;
    std::vector<CurvePoint> by_wall, by_trace;
    bool active = true;
  };
  std::vector<Run> runs;
  for (size_t gi = 0; gi < generators.size(); ++gi) {
    Run run;
    run.label = o.generators[gi].text();
    run.pt =
        std::make_unique<PathTracer>(ls->scene, *ls->tracer, *generators[gi], settings_of(o.common, o.common.seed));
    run.acc = Accumulator(o.common.width, o.common.height);
    runs.push_back(std::move(run));
  }

  Progress bar;
  try {
    for (bool any = true; any;) {
      any = false;
      for (size_t gi = 0; gi < runs.size(); ++gi) {
        Run& run = runs[gi];
        if (!run.active) continue;
        const FrameStats f = run.pt->render_frame(static_cast<uint32_t>(run.frames), run.acc);
        run.total.add(f);
        ++run.frames;
        const ErrorMetrics m = compare_images(run.acc.mean(), ref.image, tm);
        run.by_wall.push_back({run.total.wall_s, m.rel_mse});
        run.by_trace.push_back({run.total.trace_s, m.rel_mse});
        std::vector<std::string> row = {ls->scene.name,
                                        o.scene,
                                        run.label,
                                        o.generators[gi].name,
                                        generators[gi]->params(),
                                        o.common.tracer.name,
                                        ls->tracer->params(),
                                        std::to_string(o.common.width),
                                        std::to_string(o.common.height),
                                        std::to_string(o.common.seed),
                                        ref.kind == "file" ? std::string() : std::to_string(o.ref_frames),
                                        std::to_string(o.common.max_depth),
                                        std::to_string(o.common.rr_depth),
                                        tone,
                                        ref.path,
                                        std::to_string(run.frames),
                                        num(run.total.wall_s),
                                        num(run.total.trace_s),
                                        num(run.total.gen_s),
                                        num(f.wall_s * 1e3),
                                        num(f.trace_s * 1e3),
                                        std::to_string(run.total.rays()),
                                        num(m.rel_mse),
                                        num(m.mse),
                                        num(m.rmse),
                                        num(m.psnr),
                                        num(m.ssim),
                                        std::to_string(run.total.non_finite)};
        row.insert(row.end(), prov.begin(), prov.end());
        csv.write_row(row);
        run.active = run.total.wall_s < o.time_s && run.frames < o.max_frames;
        any = any || run.active;
      }
      // Progress in hundredths of the whole time budget (the bar counts them as its steps).
      double done = 0;
      for (const Run& r : runs) done += std::min(r.total.wall_s, o.time_s);
      bar.update(
          0, 1, static_cast<int>(100 * done / (o.time_s * static_cast<double>(runs.size()))), 100,
          fmt::format("{}: {:.0f} of {:.0f} s", ls->scene.name, done, o.time_s * static_cast<double>(runs.size())));
    }
  } catch (const Error& e) {
    bar.clear();
    csv.discard_if_empty();
    if (csv.rows() == 0) throw;
    throw Error(
        fmt::format("{} ({} rows measured before this are kept in {})", e.what(), csv.rows(), csv.partial_path()));
  }
  bar.clear();
  csv.finish();

  // Ratios against the baseline (the first generator), on relMSE, for the wall and the trace clock.
  const std::string summary_path = stem_path(o.out) + "-summary.csv";
  CsvWriter summary(summary_path,
                    with_provenance({"scene", "method", "baseline", "metric", "clock", "horizon_s", "error",
                                     "baseline_error", "equal_time_error_ratio", "target_error", "time_s",
                                     "baseline_time_s", "equal_error_speedup", "frames", "baseline_frames"}),
                    CsvWriter::Resume::No);
  std::printf(
      "\n%s, %dx%d, %.3g s per generator, reference %d frames (%s); error = relMSE (eps %.2g), "
      "baseline %s\n\n",
      ls->scene.name.c_str(), o.common.width, o.common.height, o.time_s, o.ref_frames, ref.kind.c_str(), kRelMseEpsilon,
      runs[0].label.c_str());
  std::printf("| generator | frames | final relMSE | final PSNR |\n|---|---:|---:|---:|\n");
  for (const Run& r : runs)
    std::printf("| %s | %d | %.4g | %.2f |\n", r.label.c_str(), r.frames, r.by_wall.back().error,
                psnr(r.acc.mean(), ref.image, tm));
  std::printf(
      "\n| generator | clock | at time s | relMSE | baseline relMSE | equal-time error ratio | to relMSE | "
      "time s | baseline time s | equal-error speedup |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  const Run& base = runs[0];
  for (size_t gi = 1; gi < runs.size(); ++gi) {
    const Run& run = runs[gi];
    for (const char* clock : {"wall", "trace"}) {
      const bool wall = std::string(clock) == "wall";
      const auto& c = wall ? run.by_wall : run.by_trace;
      const auto& b = wall ? base.by_wall : base.by_trace;
      const double horizon = std::min(c.back().time, b.back().time);
      const double e = error_at_time(c, horizon), eb = error_at_time(b, horizon);
      const double target = std::max(c.back().error, b.back().error);
      const double t = time_to_error(c, target), tb = time_to_error(b, target);
      std::vector<std::string> row = {ls->scene.name,
                                      run.label,
                                      base.label,
                                      "rel_mse",
                                      clock,
                                      num(horizon),
                                      num(e),
                                      num(eb),
                                      num(e / eb),
                                      num(target),
                                      num(t),
                                      num(tb),
                                      num(tb / t),
                                      std::to_string(run.frames),
                                      std::to_string(base.frames)};
      row.insert(row.end(), prov.begin(), prov.end());
      summary.write_row(row);
      std::printf("| %s | %s | %.3g | %.4g | %.4g | %.3f | %.4g | %.3g | %.3g | %.3f |\n", run.label.c_str(), clock,
                  horizon, e, eb, e / eb, target, t, tb, tb / t);
    }
  }
  summary.finish();
  std::printf("\nWrote %s and %s (%s, %d threads)\n", o.out.c_str(), summary_path.c_str(),
              provenance.git_revision.c_str(), provenance.threads);
  return 0;
}

int run_compare(const CompareOptions& o) {
  check_exposure(o.tone_map);
  const Image test = read_image_for("test image", o.test);
  const Image ref = read_image_for("reference image", o.reference);
  check_same_size(test, ref);
  const ToneMap tm = resolved(o.tone_map, ref);
  const ErrorMetrics m = compare_images(test, ref, tm);
  std::printf("test %s vs reference %s (%dx%d)\n", o.test.c_str(), o.reference.c_str(), ref.width, ref.height);
  std::printf("rmse %.6g\nrel_mse %.6g (eps %.2g)\nmse %.6g\npsnr %.4f dB (tone map %s, peak %.1f)\n", m.rmse,
              m.rel_mse, kRelMseEpsilon, m.mse, m.psnr, describe(tm).c_str(), kPsnrPeak);
  std::printf("ssim %.6f%s\n", m.ssim, std::isnan(m.ssim) ? " (images smaller than the 11x11 SSIM window)" : "");
  std::printf("nan_pixels %llu\ninf_pixels %llu\n", static_cast<unsigned long long>(m.nan_pixels),
              static_cast<unsigned long long>(m.inf_pixels));
  return 0;
}

}  // namespace raycoh
