// `raycoh converge`: the ratios of every generator's curve against the baseline's, per clock (the summary CSV), and
// the console tables (harness/image/converge.cpp's header comment says how they are read).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "harness/image/converge_run.h"

namespace raycoh {

// wall; trace (CPU only: the device's frames have no trace time apart); modeled_gpu (--gpu-model); the device's
// clock, measured_gpu or simulated_gpu (--device cuda). Each compared on its own, never summed with another.
std::vector<std::string> ConvergeRun::clocks() const {
  const DeviceClock* device = nullptr;
  for (const Run& r : runs_)
    if (r.device.active()) device = &r.device;
  std::vector<std::string> out{"wall"};
  if (!device) out.push_back("trace");
  if (gpu_model_) out.push_back("modeled_gpu");
  if (device) out.push_back(device->clock_name());
  return out;
}

SummaryRow ConvergeRun::compare(const Run& run, const std::string& clock) const {
  const Run& base = runs_[0];
  auto curve = [&clock](const Run& x) -> const std::vector<CurvePoint>& {
    return clock == "wall"          ? x.by_wall
           : clock == "trace"       ? x.by_trace
           : clock == "modeled_gpu" ? x.gpu.curve
                                    : x.device.curve;
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
  if (against_.noise) {
    const double n = against_.noise->rel_mse, smaller = std::min(cc.error, cc.baseline_error);
    r.ref_noise_rel_mse = n;
    ReferenceNoise relative;  // the summary's figures are relMSE
    relative.rel_mse = n;
    relative.rel_mse_se = against_.noise->rel_mse_se;
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
  r.render_device = o_.common.device;
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
      ls_->scene.name.c_str(), o_.common.width, o_.common.height, o_.time_s, ref_frames_text.c_str(),
      against_.ref.kind.c_str(), kRelMseEpsilon, runs_[0].label.c_str(), o_.common.protocol.c_str(),
      metric_space_name(o_.common.metrics));
  std::printf(
      "| generator | frames | final relMSE | relMSE−ref noise | ref noise share | final PSNR | wall s | modeled GPU ms "
      "per frame | device GPU ms per frame |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  const double nan = std::nan("");
  for (const Run& r : runs_)
    if (r.frames > 0) {
      const double e = r.by_wall.back().error;
      const double share = against_.noise ? (e > 0 ? against_.noise->rel_mse / e : 1.0) : nan;
      std::printf(
          "| %s | %d | %.4g | %.4g | %.1f%% | %.2f | %.3g | %s | %s |\n", r.label.c_str(), r.frames, e,
          against_.noise ? minus_noise(e, against_.noise->rel_mse) : nan, 100 * share,
          psnr(r.acc.mean(), against_.ref.image, against_.tm, o_.common.metrics), r.total.wall_s,
          r.gpu.model ? fmt::format("{:.3g}", r.gpu.s * 1e3 / r.frames).c_str() : "-",
          r.device.active() ? fmt::format("{:.3g} ({})", r.device.s * 1e3 / r.frames, r.device.label).c_str() : "-");
      warn_reference_noise(fmt::format("{} after {} frames (relMSE)", r.label, r.frames), share);
    }
  if (gpu_model_)
    std::printf("\nmodeled_gpu: MODELED time on simt[%s] (trace launches + generation, harness/image/gpu_clock.h)\n",
                gpu_model_->params().c_str());
  for (const std::string& clock : clocks())
    if (clock.ends_with("_gpu") && clock != "modeled_gpu")
      std::printf("\n%s: %s GPU time of the device path tracer on %s (CUDA events around each frame)\n", clock.c_str(),
                  clock == "simulated_gpu" ? "SIMULATED (GPGPU-Sim)" : "MEASURED", provenance_.device.c_str());
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

}  // namespace raycoh
