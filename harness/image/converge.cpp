#include "harness/image/converge.h"

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
// time_to_error in records/curves.cpp): Monte Carlo error falls as a power of time, which this reads exactly.
// --shard I/N: the shard renders its own generators (units scene x generator, records/shard.h) and the baseline
// beside them, so that every ratio compares two curves timed in one process on one machine; the baseline's rows
// are written only by the shard that owns it. `raycoh merge` joins both files of every shard.
// The third clock, modeled_gpu, is each frame's modeled time on the `simt` tracer's GPU (--gpu-model,
// harness/image/gpu_clock.h: what it includes and what not), computed on the same rays after the timed frame: its own
// columns and its own summary rows, never added to a measured time.
// --device cuda: every frame on the device path tracer (harness/image/frame_source.h); a fourth clock, the frame's
// GPU time from its CUDA events (harness/image/device_clock.h: measured on a GPU, simulated under GPGPU-Sim), in its
// own columns (frame_gpu_ms, gpu_s) and summary rows (clock measured_gpu / simulated_gpu); no trace clock (the
// device's trace is not timed apart). The modeled clock, when asked for, models the CPU's render of the same frame.
// --denoise oidn: at 1, 2, 4, 8, ... frames the running mean is also denoised (OIDN with the first hits' albedo and
// normal over the same frames, harness/image/denoise_eval.h) and its error written in the row's denoised_* columns,
// outside the frame's timing (denoise_ms); the summary's ratios stay on the raw curves.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "core/durable_file.h"
#include "core/error.h"
#include "harness/common/cli.h"
#include "harness/common/command.h"
#include "harness/common/progress.h"
#include "harness/image/converge_run.h"
#include "harness/image/gpu_clock.h"
#include "harness/image/render_cli.h"
#include "harness/image/render_common.h"
#include "plugins/recorded_params.h"
#include "plugins/tracer_registry.h"
#include "records/converge_row.h"
#include "records/record_csv.h"
#include "records/recorded_columns.h"
#include "shading/metrics.h"
#include "shading/reference.h"

namespace raycoh {

namespace fs = std::filesystem;

namespace {

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

}  // namespace

std::string summary_path_of(const ConvergeOptions& o) { return converge_summary_path(o.out); }

ConvergeRun::ConvergeRun(const ConvergeOptions& o, const Provenance& p)
    : o_(o),
      provenance_(p),
      csv_(o.out, converge_schema(), CsvWriter::Options::once(o.common.force, same_command(p))),
      summary_(summary_path_of(o), summary_schema(), CsvWriter::Options::once(o.common.force, same_command(p))),
      denoise_(o.denoise) {
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
  against_.ref = obtain_reference(*ls_, o.scene, o.common, o.ref_frames, o.cache_dir, o.reference);
  against_.tm = resolved(o.common.tone_map, against_.ref.image);
  against_.noise = noise_of_reference(against_.ref, against_.tm, o.common.metrics);
  provenance_.device = device_of(o.common.tracer);
  if (o.gpu_model != "none") gpu_model_ = make_tracer(parse_plugin_spec(o.gpu_model), ls_->scene, ls_->bvh);
  for (size_t gi = 0; gi < generators_.size(); ++gi) {
    Run run;
    run.label = o.generators[gi].text();
    run.active = renders(gi);
    if (run.active) {
      run.source =
          std::make_unique<FrameSource>(o.common.device, *ls_, *generators_[gi], settings_of(o.common, o.common.seed));
      run.device.label = run.source->clock();
      if (run.source->on_device()) provenance_.device = run.source->device_name();
      run.acc = Accumulator(o.common.width, o.common.height);
      if (denoise_.active()) run.aux = AuxAccumulators(o.common.width, o.common.height);
      if (gpu_model_)
        run.gpu.model =
            std::make_unique<FrameModel>(ls_->scene, *ls_->tracer, *gpu_model_, make_generator(o.generators[gi]),
                                         settings_of(o.common, o.common.seed));
    }
    runs_.push_back(std::move(run));
  }
}

ConvergeRow ConvergeRun::row_of(size_t gi, const SourcedFrame& sf, const ErrorMetrics& m, bool modeled) const {
  const FrameStats& f = sf.stats;
  const Run& run = runs_[gi];
  ConvergeRow r;
  r.scene = ls_->scene.name;
  r.scene_spec = o_.scene;
  r.scene_fingerprint = fingerprint_;
  r.method = run.label;
  r.generator = o_.generators[gi].name;
  r.generator_params = generators_[gi]->params();
  // On the device every batch is traced by the device trace kernel (BVH2), not by --tracer.
  const bool device = run.device.active();
  r.tracer = device ? "cuda" : o_.common.tracer.name;
  r.tracer_params = device ? "bvh=bvh2" : ls_->tracer->params();
  r.recorded = recorded_columns(r.generator, r.generator_params, r.tracer, r.tracer_params);
  r.width = o_.common.width;
  r.height = o_.common.height;
  r.seed = o_.common.seed;
  if (o_.ref_frames_known) r.ref_frames = o_.ref_frames;
  r.max_depth = o_.common.max_depth;
  r.rr_depth = o_.common.rr_depth;
  r.tone_map = describe(against_.tm);
  r.reference = against_.ref.path;
  r.protocol = o_.common.protocol;
  r.metrics = metric_space_name(o_.common.metrics);
  r.frame = run.frames;
  const double nan = std::nan("");  // trace and generation time: not measured apart on the device
  r.wall_s = run.total.wall_s;
  r.trace_s = device ? nan : run.total.trace_s;
  r.gen_s = device ? nan : run.total.gen_s;
  r.frame_wall_ms = f.wall_s * 1e3;
  r.frame_trace_ms = device ? nan : f.trace_s * 1e3;
  r.rays = run.total.rays();
  r.rel_mse = m.rel_mse;
  r.mse = m.mse;
  r.rmse = m.rmse;
  r.psnr = m.psnr;
  r.ssim = m.ssim;
  if (against_.noise) {
    const NoiseCorrected c =
        correct_for_noise(*against_.noise, m.mse, m.rel_mse, std::pow(10.0, -m.psnr / 10.0) * kPsnrPeak * kPsnrPeak);
    r.ref_noise_mse = against_.noise->mse;
    r.ref_noise_rel_mse = against_.noise->rel_mse;
    r.ref_noise_share = c.share;
    r.mse_corr = c.mse;
    r.rel_mse_corr = c.rel_mse;
    r.psnr_corr = c.psnr;
  }
  r.non_finite_samples = run.total.non_finite;
  if (run.gpu.model) {
    const ResultKey model = result_key("simt", gpu_model_->params(), gpu_model_->bvh_layout());
    r.gpu_model = model.label(true);
    r.gpu_preset = model.preset;
    r.modeled_frame = modeled ? 1 : 0;
    r.frame_modeled_gen_ms = run.gpu.last.gen_ms;
    r.frame_modeled_trace_ms = run.gpu.last.trace_ms;
    r.frame_modeled_gpu_ms = run.gpu.last.ms();
    r.modeled_gpu_s = run.gpu.s;
  }
  r.provenance = provenance_;
  r.denoise = denoiser_name(o_.denoise);
  r.render_device = o_.common.device;
  if (device) {
    r.gpu_clock = run.device.label;
    r.frame_gpu_ms = sf.gpu_ms;
    r.frame_gpu_stages = sf.gpu_stages;
    r.gpu_s = run.device.s;
  }
  return r;
}

void ConvergeRun::add_denoised(const Run& run, const Image& mean, ConvergeRow& r) const {
  if (!denoise_.active() || (run.frames & (run.frames - 1)) != 0) return;
  double seconds = 0;
  const ErrorMetrics m =
      compare_images(denoise_.denoise(mean, run.aux, &seconds), against_.ref.image, against_.tm, o_.common.metrics);
  r.denoised_rel_mse = m.rel_mse;
  r.denoised_mse = m.mse;
  r.denoised_rmse = m.rmse;
  r.denoised_psnr = m.psnr;
  r.denoised_ssim = m.ssim;
  r.denoise_ms = seconds * 1e3;
  if (against_.noise) {
    const NoiseCorrected c =
        correct_for_noise(*against_.noise, m.mse, m.rel_mse, std::pow(10.0, -m.psnr / 10.0) * kPsnrPeak * kPsnrPeak);
    r.denoised_mse_corr = c.mse;
    r.denoised_rel_mse_corr = c.rel_mse;
    r.denoised_psnr_corr = c.psnr;
  }
}

// One frame of every generator still short of its time; false when none is left.
bool ConvergeRun::render_round() {
  bool any = false;
  for (size_t gi = 0; gi < runs_.size(); ++gi) {
    Run& run = runs_[gi];
    if (!run.active) continue;
    const SourcedFrame sf =
        run.source->render(static_cast<uint32_t>(run.frames), run.acc, denoise_.active() ? &run.aux : nullptr);
    const FrameStats& f = sf.stats;
    run.total.add(f);
    // The modeled GPU clock, after the timed frame: its own sum, never added to a measured time. A device frame's
    // rays are other samples than the CPU's, so its model is not checked against them (gpu_clock.h).
    const bool modeled = run.gpu.model && (run.frames % o_.model_every == 0);
    if (modeled)
      run.gpu.last = run.device.active() ? run.gpu.model->model(static_cast<uint32_t>(run.frames))
                                         : run.gpu.model->model(static_cast<uint32_t>(run.frames), f);
    ++run.frames;
    const Image mean = run.acc.mean();
    const ErrorMetrics m = compare_images(mean, against_.ref.image, against_.tm, o_.common.metrics);
    run.by_wall.push_back({run.total.wall_s, m.rel_mse});
    if (!run.device.active()) run.by_trace.push_back({run.total.trace_s, m.rel_mse});
    if (run.device.active()) run.device.add(sf.gpu_ms, m.rel_mse);  // the device's clock, its own sum
    if (run.gpu.model) {
      run.gpu.s += run.gpu.last.ms() * 1e-3;
      run.gpu.curve.push_back({run.gpu.s, m.rel_mse});
    }
    if (owns(gi)) {
      ConvergeRow row = row_of(gi, sf, m, modeled);
      add_denoised(run, mean, row);
      csv_.write(row);
    }
    run.active = run.total.wall_s < o_.time_s && run.frames < o_.max_frames;
    any = any || run.active;
  }
  return any;
}

void ConvergeRun::render() {
  denoise_.notice_if_missing();
  Progress bar;
  std::vector<bool> counted;  // the runs with work at the start
  for (const Run& r : runs_) counted.push_back(r.active);
  const auto runs = std::count(counted.begin(), counted.end(), true);
  try {
    if (runs == 0) {  // a shard with no unit
      csv_.finish();
      return;
    }
    for (bool any = true; any;) {
      any = render_round();
      // Progress in hundredths of the runs' budgets: each run is as far as the nearer of its two ends, the time
      // budget or --max-frames (the bar counts hundredths as its steps).
      double done = 0;
      int frames = 0;
      for (size_t i = 0; i < runs_.size(); ++i) {
        if (!counted[i]) continue;
        const Run& r = runs_[i];
        frames += r.frames;
        done += r.active ? std::min(1.0, std::max(r.total.wall_s / o_.time_s, double(r.frames) / o_.max_frames)) : 1.0;
      }
      bar.update(0, 1, static_cast<int>(100 * done / runs), 100,
                 fmt::format("{}: {} frames; a generator stops at {:g} s or {} frames", ls_->scene.name, frames,
                             o_.time_s, o_.max_frames));
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
    std::string generators, time, shard = "0/1", denoise = "none";  // defaults from ConvergeOptions
  };
  auto s = std::make_shared<State>();
  s->generators = join_specs(s->o.generators);
  s->time = fmt::format("{}s", s->o.time_s);
  CLI::App* cmd = parent.add_subcommand(
      "converge", "error against wall-clock, trace, modeled and device GPU time; equal-time and equal-error ratios");
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
  cmd->add_option("--denoise", s->denoise, "none|oidn: also the error after denoising, at frames 1, 2, 4, 8, ...")
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
            s->o.denoise = parse_denoiser("--denoise", s->denoise);
            return run_converge(s->o, provenance);
          }};
}

}  // namespace raycoh
