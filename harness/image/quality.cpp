#include "harness/image/quality.h"

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
#include "harness/common/cli.h"
#include "harness/common/command.h"
#include "harness/common/progress.h"
#include "harness/image/denoise_eval.h"
#include "harness/image/quality_measure.h"
#include "harness/image/render_cli.h"
#include "harness/image/render_common.h"
#include "records/quality_row.h"
#include "records/record_csv.h"
#include "shading/flip.h"
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
      .require("reference_kind", {o.reference.empty() ? "cache" : "file"})
      .require("denoise", {denoiser_name(o.denoise)})
      .require("render_device", {o.common.device});
  if (!o.reference.empty()) rule.require("reference", {o.reference});
  return require_provenance(rule, p);
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
        denoise_(o.denoise),
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
  DenoiseEval denoise_;
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
  r.denoise = denoiser_name(o_.denoise);
  r.render_device = o_.common.device;
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
                                     o_.scenes.size() * o_.generators.size(), denoise_);
  QualityRow row = head(o_.scenes[si], gi);
  row.scene = ls.scene.name;
  row.scene_triangles = ls.scene.triangle_count();
  row.scene_fingerprint = fingerprint_;
  row.generator = o_.generators[gi].name;
  row.generator_params = generators_[gi]->params();
  const bool device = !m.gpu_clock.empty();  // every batch traced by the device trace kernel (BVH2), not --tracer
  row.tracer = device ? "cuda" : o_.common.tracer.name;
  row.tracer_params = device ? "bvh=bvh2" : ls.tracer->params();
  if (device) row.provenance.device = m.device_name;
  row.recorded = recorded_columns(row.generator, row.generator_params, row.tracer, row.tracer_params);
  if (ref_kind_ != "file") row.ref_seed = o_.common.seed + kReferenceSeedOffset;
  row.exposure = tm.exposure;
  row.reference = ref.path;
  row.ref_non_finite_samples = ref.non_finite;
  fill_measurements(row, m, o_.bias_renders, o_.frames, noise);
  fill_denoised(row, m, noise);
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
    row.flip_hdr_renders = f.per_test;
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
      if (owns(si, gi)) {
        rows_.push_back(*finished(spec, gi));
        if (o_.after_row && o_.after_row(rows_.back())) break;
      }
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
    if (o_.after_row && o_.after_row(rows_.back())) break;
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
  denoise_.notice_if_missing();
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
  if (!o_.console) return 0;
  print_quality(o_, rows_);
  for (const QualityRow& r : rows_)
    if (r.render_device != "cpu")
      std::printf("%s %s: %.3f ms of %s GPU time per frame on %s (device path tracer, CUDA events)\n", r.scene.c_str(),
                  r.method.c_str(), r.gpu_frame_ms, r.gpu_clock.c_str(), r.provenance.device.c_str());
  if (o_.denoise != Denoiser::None) print_denoised_quality(rows_);
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
    std::string scenes, generators, shard = "0/1", denoise = "none";
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
  cmd->add_option("--denoise", s->denoise, "none|oidn: every figure on the denoised renders too")
      ->capture_default_str();
  bind_render_common(cmd, s->o.common, s->text);
  bind_protocol(cmd, s->protocol, true);
  return {cmd, [s, cmd](const Provenance& provenance) {
            resolve_render_common(s->o.common, s->text);
            s->o.shard = parse_shard("--shard", s->shard);
            s->o.denoise = parse_denoiser("--denoise", s->denoise);
            resolve_protocol(cmd, s->protocol, s->o.common, &s->o.frames, "--frames", &s->o.ref_frames, "--ref-frames");
            adopt_reference_frames(cmd, s->o.reference, &s->o.ref_frames);
            s->o.scenes = split_scenes("--scenes", s->scenes);
            s->o.generators = split_nonempty("--generators", s->generators);
            s->o.crops = parse_crops(s->text.crops);
            return run_quality(s->o, provenance);
          }};
}

}  // namespace raycoh
