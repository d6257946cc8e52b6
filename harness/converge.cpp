// `raycoh converge`: per generator, frames are rendered round-robin (one frame of each in turn, so that load changes
// on the machine hit all of them alike) until each has rendered --time seconds of frames (wall clock of the frames
// themselves; the error evaluation after each frame is not counted). One CSV row per generator and frame:
// cumulative wall and trace time and the error of the running mean against the reference. Ratios against the
// first generator (the baseline), on relMSE, for both clocks, go to <out stem>-summary.csv:
//   equal-time error ratio  e_g(T) / e_base(T) at T = the shorter of the two curves' last times
//                           (< 1: the generator is more accurate in the same time);
//   equal-error speedup     t_base(E) / t_g(E) with E = the larger of the two final errors, the error both reach
//                           (> 1: the generator reaches it sooner).
// Curves are read by interpolating linearly in (log time, log error) between frames (error_at_time,
// time_to_error in curves.cpp): Monte Carlo error falls as a power of time, which this reads exactly.
// --shard I/N: the shard renders its own generators (units scene x generator, records/shard.h) and the baseline
// beside them, so that every ratio compares two curves timed in one process on one machine; the baseline's rows
// are written only by the shard that owns it. `raycoh merge` joins both files of every shard.
// The third clock, modeled_gpu, is each frame's modeled time on the `simt` tracer's GPU (--gpu-model,
// harness/gpu_clock.h: what it includes and what not), computed on the same rays after the timed frame: its own
// columns and its own summary rows, never added to a measured time.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "core/durable_file.h"
#include "core/error.h"
#include "harness/cli.h"
#include "harness/command.h"
#include "harness/gpu_clock.h"
#include "harness/merge.h"
#include "harness/progress.h"
#include "records/record_csv.h"
#include "harness/render_common.h"
#include "plugins/tracer_registry.h"
#include "shading/metrics.h"
#include "shading/reference.h"

namespace raycoh {

namespace fs = std::filesystem;

namespace {

// One generator's running mean after one more frame.
struct ConvergeRow {
  std::string scene, scene_spec, scene_fingerprint, method, generator, generator_params, tracer, tracer_params;
  int width = 0, height = 0;
  uint32_t seed = 0;
  std::optional<int> ref_frames;  // absent for an explicit --reference file
  int max_depth = 0, rr_depth = 0;
  std::string tone_map, reference;
  std::string protocol, metrics;  // --protocol; space of psnr/ssim
  int frame = 0;                  // frames rendered so far
  double wall_s = 0, trace_s = 0, gen_s = 0, frame_wall_ms = 0, frame_trace_ms = 0;
  uint64_t rays = 0;
  double rel_mse = 0, mse = 0, rmse = 0, psnr = 0, ssim = 0;
  // The reference's own noise (empty without a half reference) and the figures with it taken out
  // (shading/metrics.h correct_for_noise, as quality's columns of the same names).
  double ref_noise_mse = std::nan(""), ref_noise_rel_mse = std::nan(""), ref_noise_share = std::nan(""),
         mse_corr = std::nan(""), rel_mse_corr = std::nan(""), psnr_corr = std::nan("");
  uint64_t non_finite_samples = 0;
  // Modeled GPU clock (empty without --gpu-model): this frame's modeled generation, trace and total, and the
  // cumulative total. modeled_frame 0: not modeled (--model-every), the last modeled frame's figures held.
  std::string gpu_model;
  std::optional<int> modeled_frame;
  double frame_modeled_gen_ms = std::nan(""), frame_modeled_trace_ms = std::nan(""),
         frame_modeled_gpu_ms = std::nan(""), modeled_gpu_s = std::nan("");
  Provenance provenance;
};

const Schema<ConvergeRow>& converge_schema() {
  using namespace csv_format;
  using R = ConvergeRow;
  using G = GeneralOrEmpty;
  static const Schema<R> schema = [] {
    Schema<R> s = {
        column("scene", &R::scene, Text{}),
        column("scene_spec", &R::scene_spec, Text{}),
        column("scene_fingerprint", &R::scene_fingerprint, Text{}),
        column("method", &R::method, Text{}),
        column("generator", &R::generator, Text{}),
        column("generator_params", &R::generator_params, Text{}),
        column("tracer", &R::tracer, Text{}),
        column("tracer_params", &R::tracer_params, Text{}),
        column("width", &R::width, Integer<int>{}),
        column("height", &R::height, Integer<int>{}),
        column("seed", &R::seed, Integer<uint32_t>{}),
        column("ref_frames", &R::ref_frames, Optional<Integer<int>>{}),
        column("max_depth", &R::max_depth, Integer<int>{}),
        column("rr_depth", &R::rr_depth, Integer<int>{}),
        column("tone_map", &R::tone_map, Text{}),
        column("reference", &R::reference, Text{}),
        column("protocol", &R::protocol, Text{}),
        column("metrics", &R::metrics, Text{}),
        column("frame", &R::frame, Integer<int>{}),
        column("wall_s", &R::wall_s, G{}),
        column("trace_s", &R::trace_s, G{}),
        column("gen_s", &R::gen_s, G{}),
        column("frame_wall_ms", &R::frame_wall_ms, G{}),
        column("frame_trace_ms", &R::frame_trace_ms, G{}),
        column("rays", &R::rays, Integer<uint64_t>{}),
        column("rel_mse", &R::rel_mse, G{}),
        column("mse", &R::mse, G{}),
        column("rmse", &R::rmse, G{}),
        column("psnr", &R::psnr, G{}),
        column("ssim", &R::ssim, G{}),
        column("ref_noise_mse", &R::ref_noise_mse, G{}),
        column("ref_noise_rel_mse", &R::ref_noise_rel_mse, G{}),
        column("ref_noise_share", &R::ref_noise_share, G{}),
        column("mse_corr", &R::mse_corr, G{}),
        column("rel_mse_corr", &R::rel_mse_corr, G{}),
        column("psnr_corr", &R::psnr_corr, G{}),
        column("non_finite_samples", &R::non_finite_samples, Integer<uint64_t>{}),
        column("gpu_model", &R::gpu_model, Text{}),
        column("modeled_frame", &R::modeled_frame, Optional<Integer<int>>{}),
        column("frame_modeled_gen_ms", &R::frame_modeled_gen_ms, G{}),
        column("frame_modeled_trace_ms", &R::frame_modeled_trace_ms, G{}),
        column("frame_modeled_gpu_ms", &R::frame_modeled_gpu_ms, G{}),
        column("modeled_gpu_s", &R::modeled_gpu_s, G{}),
    };
    append_columns(s, provenance_schema(), &R::provenance);
    return s;
  }();
  return schema;
}

// One generator against the baseline on one clock.
struct SummaryRow {
  std::string scene, method, baseline, metric, clock;
  double horizon_s = 0, error = 0, baseline_error = 0, equal_time_error_ratio = 0, target_error = 0, time_s = 0,
         baseline_time_s = 0, equal_error_speedup = 0;
  // The reference's noise (relMSE; empty without a half reference), its share of the smaller of error and
  // baseline_error, both errors with it taken out and their ratio. equal_error_speedup needs no corrected twin: the
  // noise is the same constant in both curves, so both reach target_error - noise at the times they reach
  // target_error.
  double ref_noise_rel_mse = std::nan(""), ref_noise_share = std::nan(""), error_corr = std::nan(""),
         baseline_error_corr = std::nan(""), equal_time_error_ratio_corr = std::nan("");
  // The noise estimate's standard error over the smaller error: the share of error_corr that is still the
  // reference's noise.
  double ref_noise_residual_share = std::nan("");
  int frames = 0, baseline_frames = 0;
  Provenance provenance;
};

const Schema<SummaryRow>& summary_schema() {
  using namespace csv_format;
  using R = SummaryRow;
  using G = GeneralOrEmpty;
  static const Schema<R> schema = [] {
    Schema<R> s = {
        column("scene", &R::scene, Text{}),
        column("method", &R::method, Text{}),
        column("baseline", &R::baseline, Text{}),
        column("metric", &R::metric, Text{}),
        column("clock", &R::clock, Text{}),
        column("horizon_s", &R::horizon_s, G{}),
        column("error", &R::error, G{}),
        column("baseline_error", &R::baseline_error, G{}),
        column("equal_time_error_ratio", &R::equal_time_error_ratio, G{}),
        column("target_error", &R::target_error, G{}),
        column("time_s", &R::time_s, G{}),
        column("baseline_time_s", &R::baseline_time_s, G{}),
        column("equal_error_speedup", &R::equal_error_speedup, G{}),
        column("ref_noise_rel_mse", &R::ref_noise_rel_mse, G{}),
        column("ref_noise_share", &R::ref_noise_share, G{}),
        column("ref_noise_residual_share", &R::ref_noise_residual_share, G{}),
        column("error_corr", &R::error_corr, G{}),
        column("baseline_error_corr", &R::baseline_error_corr, G{}),
        column("equal_time_error_ratio_corr", &R::equal_time_error_ratio_corr, G{}),
        column("frames", &R::frames, Integer<int>{}),
        column("baseline_frames", &R::baseline_frames, Integer<int>{}),
    };
    append_columns(s, provenance_schema(), &R::provenance);
    return s;
  }();
  return schema;
}

void check_converge(const ConvergeOptions& o) {
  check_common(o.common, true);
  check_frames("--max-frames", o.max_frames);
  check_frames("--ref-frames", o.ref_frames);
  if (!(o.time_s > 0) || !std::isfinite(o.time_s) || o.time_s > 1e6)
    throw Error(fmt::format("--time {}: must be more than 0 and at most 1e6 seconds", o.time_s));
  check_scene_spec("--scene", o.scene);
  if (!o.reference.empty() && !fs::is_regular_file(o.reference))
    throw Error(fmt::format("--reference {}: no such image file", o.reference));
  check_output_file("--out", o.out);
  check_output_folder("--cache", o.cache_dir.empty() ? default_cache_dir() : o.cache_dir);
  check_frames("--model-every", o.model_every);
  if (o.gpu_model != "none" && parse_plugin_spec(o.gpu_model).name != "simt")
    throw Error(
        fmt::format("--gpu-model {}: expected a simt tracer (simt, simt:preset=h100, ...) or none", o.gpu_model));
}

std::string summary_path_of(const ConvergeOptions& o) { return stem_path(o.out) + "-summary.csv"; }

// One generator's progress.
struct Run {
  std::string label;
  std::unique_ptr<PathTracer> pt;
  Accumulator acc;
  FrameStats total;
  int frames = 0;
  std::vector<CurvePoint> by_wall, by_trace;
  bool active = true;
  // The modeled GPU clock (absent without --gpu-model).
  std::unique_ptr<FrameModel> model;
  ModeledFrame modeled;  // the last modeled frame
  double modeled_s = 0;
  std::vector<CurvePoint> by_gpu;
};

class ConvergeRun {
 public:
  ConvergeRun(const ConvergeOptions& o, const Provenance& p);
  // Both files already hold this very command's finished result: nothing is rendered.
  bool complete() const { return csv_.already_complete(); }
  void render();
  void summarize();

 private:
  bool render_round();
  ConvergeRow row_of(size_t gi, const FrameStats& f, const ErrorMetrics& m, bool modeled) const;
  // --shard: the generators whose rows this shard writes; it renders the baseline (0) too, for its ratios.
  bool owns(size_t gi) const { return owned_[gi]; }
  bool renders(size_t gi) const { return gi == 0 || owns(gi); }
  SummaryRow compare(const Run& run, const std::string& clock) const;
  std::vector<std::string> clocks() const;

  const ConvergeOptions& o_;
  Provenance provenance_;  // with this run's device
  // A convergence curve is one timed measurement: an interrupted run starts again rather than resuming. Both
  // files are opened (and locked) before anything is rendered.
  RecordCsv<ConvergeRow> csv_;
  RecordCsv<SummaryRow> summary_;
  std::vector<std::unique_ptr<Generator>> generators_;
  std::unique_ptr<LoadedScene> ls_;
  ReferenceImage ref_;
  ToneMap tm_;                           // resolved on the reference, the same for every generator
  std::optional<ReferenceNoise> noise_;  // the reference's own noise, from its half image
  std::unique_ptr<Tracer> gpu_model_;    // the `simt` tracer of --gpu-model, null for none
  std::vector<Run> runs_;
  std::vector<bool> owned_;
  std::string fingerprint_;
};

ConvergeRun::ConvergeRun(const ConvergeOptions& o, const Provenance& p)
    : o_(o),
      provenance_(p),
      csv_(o.out, converge_schema(), CsvWriter::Options::once(o.common.force, same_command(p))),
      summary_(summary_path_of(o), summary_schema(), CsvWriter::Options::once(o.common.force, same_command(p))) {
  if (csv_.already_complete() != summary_.already_complete())
    throw Error(fmt::format("--out {}: {} is finished but {} is not; pass --force to measure again", o.out,
                            csv_.already_complete() ? o.out : summary_path_of(o),
                            csv_.already_complete() ? summary_path_of(o) : o.out));
  if (complete()) return;
  generators_ = make_generators("--generators", o.generators);
  std::vector<std::string> units;
  for (const PluginSpec& g : o.generators) units.push_back(render_unit(o.scene, g.text()));
  owned_ = owned_units(units, o.shard);
  if (std::find(owned_.begin(), owned_.end(), true) == owned_.end()) return;  // a shard with no unit: empty files
  ls_ = load(o.scene, o.common.tracer);
  fingerprint_ = scene_fingerprint(o.scene);
  ref_ = obtain_reference(*ls_, o.scene, o.common, o.ref_frames, o.cache_dir, o.reference);
  tm_ = resolved(o.common.tone_map, ref_.image);
  noise_ = noise_of_reference(ref_, tm_, o.common.metrics);
  provenance_.device = device_of(o.common.tracer);
  if (o.gpu_model != "none") gpu_model_ = make_tracer(parse_plugin_spec(o.gpu_model), ls_->scene, ls_->bvh);
  for (size_t gi = 0; gi < generators_.size(); ++gi) {
    Run run;
    run.label = o.generators[gi].text();
    run.active = renders(gi);
    if (run.active) {
      run.pt = std::make_unique<PathTracer>(ls_->scene, *ls_->tracer, *generators_[gi],
                                            settings_of(o.common, o.common.seed));
      run.acc = Accumulator(o.common.width, o.common.height);
      if (gpu_model_)
        run.model =
            std::make_unique<FrameModel>(ls_->scene, *ls_->tracer, *gpu_model_, make_generator(o.generators[gi]),
                                         settings_of(o.common, o.common.seed));
    }
    runs_.push_back(std::move(run));
  }
}

ConvergeRow ConvergeRun::row_of(size_t gi, const FrameStats& f, const ErrorMetrics& m, bool modeled) const {
  const Run& run = runs_[gi];
  ConvergeRow r;
  r.scene = ls_->scene.name;
  r.scene_spec = o_.scene;
  r.scene_fingerprint = fingerprint_;
  r.method = run.label;
  r.generator = o_.generators[gi].name;
  r.generator_params = generators_[gi]->params();
  r.tracer = o_.common.tracer.name;
  r.tracer_params = ls_->tracer->params();
  r.width = o_.common.width;
  r.height = o_.common.height;
  r.seed = o_.common.seed;
  if (o_.ref_frames_known) r.ref_frames = o_.ref_frames;
  r.max_depth = o_.common.max_depth;
  r.rr_depth = o_.common.rr_depth;
  r.tone_map = describe(tm_);
  r.reference = ref_.path;
  r.protocol = o_.common.protocol;
  r.metrics = metric_space_name(o_.common.metrics);
  r.frame = run.frames;
  r.wall_s = run.total.wall_s;
  r.trace_s = run.total.trace_s;
  r.gen_s = run.total.gen_s;
  r.frame_wall_ms = f.wall_s * 1e3;
  r.frame_trace_ms = f.trace_s * 1e3;
  r.rays = run.total.rays();
  r.rel_mse = m.rel_mse;
  r.mse = m.mse;
  r.rmse = m.rmse;
  r.psnr = m.psnr;
  r.ssim = m.ssim;
  if (noise_) {
    const NoiseCorrected c =
        correct_for_noise(*noise_, m.mse, m.rel_mse, std::pow(10.0, -m.psnr / 10.0) * kPsnrPeak * kPsnrPeak);
    r.ref_noise_mse = noise_->mse;
    r.ref_noise_rel_mse = noise_->rel_mse;
    r.ref_noise_share = c.share;
    r.mse_corr = c.mse;
    r.rel_mse_corr = c.rel_mse;
    r.psnr_corr = c.psnr;
  }
  r.non_finite_samples = run.total.non_finite;
  if (run.model) {
    r.gpu_model = "simt[" + gpu_model_->params() + "]";
    r.modeled_frame = modeled ? 1 : 0;
    r.frame_modeled_gen_ms = run.modeled.gen_ms;
    r.frame_modeled_trace_ms = run.modeled.trace_ms;
    r.frame_modeled_gpu_ms = run.modeled.ms();
    r.modeled_gpu_s = run.modeled_s;
  }
  r.provenance = provenance_;
  return r;
}

// One frame of every generator still short of its time; false when none is left.
bool ConvergeRun::render_round() {
  bool any = false;
  for (size_t gi = 0; gi < runs_.size(); ++gi) {
    Run& run = runs_[gi];
    if (!run.active) continue;
    const FrameStats f = run.pt->render_frame(static_cast<uint32_t>(run.frames), run.acc);
    run.total.add(f);
    // The modeled GPU clock, after the timed frame: its own sum, never added to a measured time.
    const bool modeled = run.model && (run.frames % o_.model_every == 0);
    if (modeled) run.modeled = run.model->model(static_cast<uint32_t>(run.frames), f);
    ++run.frames;
    const ErrorMetrics m = compare_images(run.acc.mean(), ref_.image, tm_, o_.common.metrics);
    run.by_wall.push_back({run.total.wall_s, m.rel_mse});
    run.by_trace.push_back({run.total.trace_s, m.rel_mse});
    if (run.model) {
      run.modeled_s += run.modeled.ms() * 1e-3;
      run.by_gpu.push_back({run.modeled_s, m.rel_mse});
    }
    if (owns(gi)) csv_.write(row_of(gi, f, m, modeled));
    run.active = run.total.wall_s < o_.time_s && run.frames < o_.max_frames;
    any = any || run.active;
  }
  return any;
}

void ConvergeRun::render() {
  Progress bar;
  double budget = 0;
  for (const Run& r : runs_) budget += r.active ? o_.time_s : 0;
  try {
    if (budget == 0) {  // a shard with no unit
      csv_.finish();
      return;
    }
    for (bool any = true; any;) {
      any = render_round();
      // Progress in hundredths of the whole time budget (the bar counts them as its steps).
      double done = 0;
      for (const Run& r : runs_) done += std::min(r.total.wall_s, o_.time_s);
      bar.update(0, 1, static_cast<int>(100 * done / budget), 100,
                 fmt::format("{}: {:.0f} of {:.0f} s", ls_->scene.name, done, budget));
    }
  } catch (const Error& e) {
    bar.clear();
    csv_.discard_if_empty();
    if (csv_.rows() == 0) throw;
    throw Error(
        fmt::format("{} ({} rows measured before this are kept in {})", e.what(), csv_.rows(), csv_.partial_path()));
  }
  bar.clear();
  csv_.finish();
}

std::vector<std::string> ConvergeRun::clocks() const {
  if (gpu_model_) return {"wall", "trace", "modeled_gpu"};
  return {"wall", "trace"};
}

SummaryRow ConvergeRun::compare(const Run& run, const std::string& clock) const {
  const Run& base = runs_[0];
  auto curve = [&clock](const Run& x) -> const std::vector<CurvePoint>& {
    return clock == "wall" ? x.by_wall : clock == "trace" ? x.by_trace : x.by_gpu;
  };
  const CurveComparison cc = compare_curves(curve(run), curve(base));
  SummaryRow r;
  r.scene = ls_->scene.name;
  r.method = run.label;
  r.baseline = base.label;
  r.metric = "rel_mse";
  r.clock = clock;
  r.horizon_s = cc.horizon;
  r.error = cc.error;
  r.baseline_error = cc.baseline_error;
  r.equal_time_error_ratio = cc.equal_time_error_ratio;
  r.target_error = cc.target_error;
  r.time_s = cc.time;
  r.baseline_time_s = cc.baseline_time;
  r.equal_error_speedup = cc.equal_error_speedup;
  if (noise_) {
    const double n = noise_->rel_mse, smaller = std::min(cc.error, cc.baseline_error);
    r.ref_noise_rel_mse = n;
    ReferenceNoise relative;  // the summary's figures are relMSE
    relative.rel_mse = n;
    relative.rel_mse_se = noise_->rel_mse_se;
    const NoiseCorrected c = correct_for_noise(relative, 0, smaller, 0);
    r.ref_noise_share = c.share;
    r.ref_noise_residual_share = c.residual_share;
    r.error_corr = minus_noise(cc.error, n);
    r.baseline_error_corr = minus_noise(cc.baseline_error, n);
    r.equal_time_error_ratio_corr = r.baseline_error_corr > 0 ? r.error_corr / r.baseline_error_corr : std::nan("");
  }
  r.frames = run.frames;
  r.baseline_frames = base.frames;
  r.provenance = provenance_;
  return r;
}

// Ratios against the baseline (the first generator), on relMSE, for the wall and the trace clock and the
// modeled GPU clock.
void ConvergeRun::summarize() {
  const std::string summary_path = summary_path_of(o_);
  RecordCsv<SummaryRow>& summary = summary_;
  if (runs_.empty()) {
    summary.finish();
    std::printf("Wrote shard %s of the run to %s and %s: it owns no generator (more shards than generators)\n",
                o_.shard.text().c_str(), o_.out.c_str(), summary_path.c_str());
    return;
  }
  const std::string ref_frames_text =
      o_.ref_frames_known ? fmt::format("{} frames", o_.ref_frames) : std::string("of unknown frames");
  std::printf(
      "\n%s, %dx%d, %.3g s per generator, reference %s (%s); error = relMSE (eps %.2g), "
      "baseline %s; protocol %s, PSNR on %s\n\n",
      ls_->scene.name.c_str(), o_.common.width, o_.common.height, o_.time_s, ref_frames_text.c_str(), ref_.kind.c_str(),
      kRelMseEpsilon, runs_[0].label.c_str(), o_.common.protocol.c_str(), metric_space_name(o_.common.metrics));
  std::printf(
      "| generator | frames | final relMSE | relMSE−ref noise | ref noise share | final PSNR | wall s | modeled GPU ms "
      "per "
      "frame |\n|---|---:|---:|---:|---:|---:|---:|---:|\n");
  const double nan = std::nan("");
  for (const Run& r : runs_)
    if (r.frames > 0) {
      const double e = r.by_wall.back().error;
      const double share = noise_ ? (e > 0 ? noise_->rel_mse / e : 1.0) : nan;
      std::printf("| %s | %d | %.4g | %.4g | %.1f%% | %.2f | %.3g | %s |\n", r.label.c_str(), r.frames, e,
                  noise_ ? minus_noise(e, noise_->rel_mse) : nan, 100 * share,
                  psnr(r.acc.mean(), ref_.image, tm_, o_.common.metrics), r.total.wall_s,
                  r.model ? fmt::format("{:.3g}", r.modeled_s * 1e3 / r.frames).c_str() : "-");
      warn_reference_noise(fmt::format("{} after {} frames (relMSE)", r.label, r.frames), share);
    }
  if (gpu_model_)
    std::printf("\nmodeled_gpu: MODELED time on simt[%s] (trace launches + generation, harness/gpu_clock.h)\n",
                gpu_model_->params().c_str());
  std::printf(
      "\n| generator | clock | at time s | relMSE | baseline relMSE | equal-time error ratio | to relMSE | "
      "time s | baseline time s | equal-error speedup | equal-time ratio, ref noise out |\n"
      "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (size_t gi = 1; gi < runs_.size(); ++gi) {
    if (!owns(gi)) continue;
    for (const std::string& clock : clocks()) {
      const SummaryRow r = compare(runs_[gi], clock);
      summary.write(r);
      std::printf("| %s | %s | %.3g | %.4g | %.4g | %.3f | %.4g | %.3g | %.3g | %.3f | %.3f |\n", r.method.c_str(),
                  clock.c_str(), r.horizon_s, r.error, r.baseline_error, r.equal_time_error_ratio, r.target_error,
                  r.time_s, r.baseline_time_s, r.equal_error_speedup, r.equal_time_error_ratio_corr);
    }
  }
  summary.finish();
  std::printf("\nWrote %s and %s (%s, %d threads)\n", o_.out.c_str(), summary_path.c_str(),
              provenance_.git_revision.c_str(), provenance_.threads);
  if (!o_.shard.whole())
    std::printf(
        "This is shard %s of the run (the baseline was rendered beside its generators for the ratios); "
        "join the shards' files with raycoh merge\n",
        o_.shard.text().c_str());
}

}  // namespace

CsvLayout converge_layout() { return csv_layout(converge_schema()); }
CsvLayout converge_summary_layout() { return csv_layout(summary_schema()); }

int run_converge(const ConvergeOptions& o, const Provenance& provenance) {
  check_converge(o);
  ConvergeRun run(o, provenance);
  if (run.complete()) {
    std::printf(
        "%s and %s already hold the result of this same command (same code revision): nothing to do; pass "
        "--force to measure again\n",
        o.out.c_str(), summary_path_of(o).c_str());
    return 0;
  }
  run.render();
  run.summarize();
  return 0;
}

BoundCommand bind_converge(CLI::App& parent) {
  struct State {
    ConvergeOptions o;
    RenderText text;
    ProtocolText protocol;
    std::string generators, time, shard = "0/1";  // defaults from ConvergeOptions
  };
  auto s = std::make_shared<State>();
  s->generators = join_specs(s->o.generators);
  s->time = fmt::format("{}s", s->o.time_s);
  CLI::App* cmd = parent.add_subcommand(
      "converge", "error against wall-clock, trace and modeled GPU time; equal-time and equal-error ratios");
  cmd->add_option("--scene", s->o.scene, "scene")->capture_default_str();
  cmd->add_option("--generators", s->generators, "comma-separated generators, the first is the baseline")
      ->capture_default_str();
  cmd->add_option("--time", s->time, "render time per generator (60s, 1.5m, 500ms)")->capture_default_str();
  cmd->add_option("--max-frames", s->o.max_frames, "stop a generator after this many frames");
  cmd->add_option("--ref-frames", s->o.ref_frames, "NoOpt frames of the reference")->capture_default_str();
  cmd->add_option("--cache", s->o.cache_dir, "reference cache folder");
  cmd->add_option("--reference", s->o.reference, "use this .exr/.pfm as the reference");
  cmd->add_option("--out", s->o.out, "CSV file to write")->capture_default_str();
  cmd->add_option("--shard", s->shard,
                  "I/N: render only shard I (0-based) of N of the generators (and the baseline beside them); join "
                  "with raycoh merge")
      ->capture_default_str();
  cmd->add_option("--gpu-model", s->o.gpu_model, "modeled GPU clock: a simt tracer spec, or none")
      ->capture_default_str();
  cmd->add_option("--model-every", s->o.model_every, "model every Nth frame on the GPU, hold the others")
      ->capture_default_str();
  bind_render_common(cmd, s->o.common, s->text);
  bind_protocol(cmd, s->protocol, true);
  return {cmd, [s, cmd](const Provenance& provenance) {
            resolve_render_common(s->o.common, s->text);
            s->o.shard = parse_shard("--shard", s->shard);
            // The ci protocol leaves --max-frames unlimited (converge runs by time); paper stops at 128 frames.
            resolve_protocol(cmd, s->protocol, s->o.common, s->protocol.protocol == "ci" ? nullptr : &s->o.max_frames,
                             "--max-frames", &s->o.ref_frames, "--ref-frames");
            s->o.ref_frames_known = adopt_reference_frames(cmd, s->o.reference, &s->o.ref_frames);
            s->o.generators = split_nonempty("--generators", s->generators);
            s->o.time_s = parse_duration("--time", s->time);
            return run_converge(s->o, provenance);
          }};
}

}  // namespace raycoh
