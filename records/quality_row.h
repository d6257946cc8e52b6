// The record of one `raycoh quality` row (one scene x generator) and its CSV column table (results/README.md).
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "records/provenance.h"
#include "records/recorded_columns.h"
#include "records/schema.h"

namespace raycoh {

struct QualityRow {
  std::string scene, scene_spec;
  size_t scene_triangles = 0;
  std::string scene_fingerprint;  // shading/reference.h scene_fingerprint: `merge` refuses shards of other files
  std::string method, generator, generator_params, tracer_spec, tracer, tracer_params;
  int width = 0, height = 0, frames = 0, ref_frames = 0, bias_renders = 0;
  uint32_t seed = 0;
  std::optional<uint32_t> ref_seed;  // absent for an explicit --reference file
  int max_depth = 0, rr_depth = 0;
  std::string tone_map;  // as given (exposure=auto before resolving)
  double exposure = 0;   // resolved on the reference
  std::string reference_kind, reference;
  std::string protocol, metrics;  // --protocol; metric space of psnr/ssim ("tonemapped" | "linear")
  // NaN (written empty) where undefined, e.g. bias2 and variance for one render.
  double psnr = 0, psnr_std = 0, ssim = 0, rmse = 0, rel_mse = 0, mse = 0, mse_of_mean = 0, bias2 = 0, variance = 0;
  // The reference's own noise (NaN without a half reference) and the figures with it taken out.
  double ref_noise_mse = 0, ref_noise_rel_mse = 0, ref_noise_share = 0, mse_corr = 0, rel_mse_corr = 0, psnr_corr = 0,
         bias2_corr = 0;
  // The standard error of the noise estimate over the figure (largest over mse, rel_mse, the PSNR's MSE): the share
  // of a *_corr figure that is still the reference's noise.
  double ref_noise_residual_share = 0;
  double rel_mse_ds2 = 0, rel_mse_ds4 = 0, rel_mse_ds8 = 0;  // of the 2x/4x/8x box-downsampled images
  double rel_var = 0, rel_var_ds8 = 0;                       // their variance part (NaN for one render)
  // Bias of the mean of all frames (shading/metrics.h bias_test), luma.
  double bias_excluded = 0, bias_excluded_dark = 0, bias_excluded_bright = 0, bias_excluded_skew = 0,
         bias_excluded_ds4 = 0, bias_mean = 0, bias_mean_ci = 0, bias_mean_rel = 0, bias_z2 = 0;
  std::string bias_verdict;       // "consistent" | "biased" | "" (one frame)
  double flip = 0;                // mean LDR-FLIP of render 0's display image (NaN when flip is not available)
  double flip_hdr = 0;            // HDR-FLIP of the linear renders, mean over the R renders (NaN: not available)
  std::string flip_hdr_exposure;  // the exposures flip chose from the reference: start..stop/count
  uint64_t non_finite_samples = 0, non_finite_pixels = 0, ref_non_finite_samples = 0;
  double render_s = 0, trace_s = 0, gen_ms = 0;
  uint64_t rays = 0;
  double mray_s = 0;
  size_t below_geometric = 0, reused_rays = 0;
  // Share of the first-bounce rays (one per hit pixel and frame, over all renders) whose group is Hybrid and whose
  // own class is diffuse (generators/generator.h hybrid_diffuse_rays): the hybrid rule's exposure. 0 for
  // generators without groups.
  double hybrid_diffuse_share = 0;
  Provenance provenance;
  RecordedColumns recorded;  // tile_w .. mode (records/recorded_columns.h)
  // Per render (seeds seed .. seed + R - 1, in order), after the typed columns: relMSE, relMSE of the 8x8
  // box-downsampled render and HDR-FLIP (empty when flip is not available), so that two generators' renders of the
  // same seed can be compared pairwise (`raycoh tune`).
  std::vector<double> rel_mse_renders, rel_mse_ds8_renders, flip_hdr_renders;
  // --denoise (after the per-render columns): the denoiser asked for ("none" | "oidn", part of the row's key) and the
  // figures on the denoised renders (harness/image/denoise_eval.h), NaN (written empty) without one or when it is
  // missing.
  std::string denoise = "none";
  double denoised_psnr = std::nan(""), denoised_psnr_std = std::nan(""), denoised_ssim = std::nan(""),
         denoised_rmse = std::nan(""), denoised_rel_mse = std::nan(""), denoised_mse = std::nan(""),
         denoised_rel_mse_ds8 = std::nan(""), denoised_mse_corr = std::nan(""), denoised_rel_mse_corr = std::nan(""),
         denoised_psnr_corr = std::nan(""), denoise_s = std::nan("");
  // --device (after the denoised columns): the path tracer the renders ran on ("cpu" | "cuda", part of the row's
  // key; the device's name is the provenance's `device`), and on the device its clock ("measured" on a GPU,
  // "simulated" under GPGPU-Sim) and the GPU milliseconds per frame (CUDA events, mean over all R x frames); empty
  // on the CPU.
  std::string render_device = "cpu", gpu_clock;
  double gpu_frame_ms = std::nan("");
};

const Schema<QualityRow>& quality_schema();

}  // namespace raycoh
