// The records of `raycoh converge`: one row per generator and frame (the running mean's error after that frame) and
// one summary row per generator, clock and metric against the baseline; their CSV column tables
// (results/README.md).
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>

#include "records/device_stages.h"
#include "records/provenance.h"
#include "records/recorded_columns.h"
#include "records/schema.h"

namespace raycoh {

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
  RecordedColumns recorded;  // tile_w .. mode (records/recorded_columns.h), after the provenance
  std::string gpu_preset;    // the preset of gpu_model (empty without --gpu-model)
  // --denoise (after gpu_preset): the denoiser asked for ("none" | "oidn") and the running mean's error after
  // denoising (harness/image/denoise_eval.h), at power-of-two frame counts only (1, 2, 4, ...); NaN (written empty) on
  // the other frames, without a denoiser, or when it is missing. denoise_ms: the denoiser's wall time (not in wall_s).
  std::string denoise = "none";
  double denoised_rel_mse = std::nan(""), denoised_mse = std::nan(""), denoised_rmse = std::nan(""),
         denoised_psnr = std::nan(""), denoised_ssim = std::nan(""), denoised_mse_corr = std::nan(""),
         denoised_rel_mse_corr = std::nan(""), denoised_psnr_corr = std::nan(""), denoise_ms = std::nan("");
  // --device (after the denoised columns): the path tracer the frames were rendered on ("cpu" | "cuda"), and on the
  // device its clock: "measured" (a GPU) or "simulated" (GPGPU-Sim), this frame's GPU milliseconds (CUDA events
  // around the frame) and the cumulative GPU seconds; empty on the CPU. Never added to wall_s or modeled_gpu_s.
  std::string render_device = "cpu", gpu_clock;
  double frame_gpu_ms = std::nan(""), gpu_s = std::nan("");
  DeviceStageMs frame_gpu_stages;  // frame_gpu_ms by stage (records/device_stages.h); empty on the CPU
};

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
  std::string render_device = "cpu";  // --device the curves were rendered on (after the provenance)
};

const Schema<ConvergeRow>& converge_schema();
const Schema<SummaryRow>& summary_schema();

// Where the summary of the curves in `out` goes: <out stem>-summary.csv.
std::string converge_summary_path(const std::string& out);

}  // namespace raycoh
