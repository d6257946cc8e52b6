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
//   denoised_*: --denoise oidn: those figures of each render after OIDN (harness/image/denoise_eval.h); empty without
//   it.
// --device cuda renders every frame on the device path tracer (harness/image/frame_source.h), the same figures from
// the same accumulation; the row adds render_device, gpu_clock and gpu_frame_ms (trace_s, gen_ms and mray_s empty:
// not measured apart on the device; hybrid_diffuse_share counted there after each frame's span).
// --protocol ci|paper sets resolution, frames, reference frames and the metric space at once (render_options.h);
// --metrics linear computes PSNR/SSIM on linear radiance (the paper's protocol) instead of the tone-mapped image. The
// console shows the Table 2 layout (one row per generator, one column per scene, PSNR) and a detailed table. Images of
// every render 0, the reference and the crops go to --images. Resume: rows already in <out>.partial from an interrupted
// run with the same settings, scene, method and git revision are kept, not rendered again.
// --shard I/N: only the shard's scene x generator units (records/shard.h); a scene none of them is of is not
// loaded, the reference comes from the cache (its entry lock lets one shard render it while the others wait), its
// image is written by the shard of the scene's first generator, and `raycoh merge` joins the shards' files.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/params.h"
#include "harness/image/render_options.h"
#include "records/provenance.h"
#include "records/quality_row.h"
#include "records/shard.h"
#include "shading/denoise.h"

namespace raycoh {

// `raycoh quality --scenes ... --generators noopt,ours --frames 128 --ref-frames 4096`
struct QualityOptions {
  RenderCommon common;
  std::vector<std::string> scenes{"cornell"};
  std::vector<PluginSpec> generators{{"noopt", ""}, {"ours", ""}};
  int frames = 32;        // --frames [1, 1 << 20]: frames per render
  int ref_frames = 512;   // --ref-frames [1, 1 << 20]: NoOpt frames of the reference
  int bias_renders = 4;   // --bias-renders [1, 256]: independent renders per generator (seeds seed .. seed+R-1)
  std::string cache_dir;  // --cache: reference cache folder ("" = $RAYCOH_CACHE or results/cache)
  std::string reference;  // --reference: use this .exr/.pfm as the reference (one scene only) instead of the cache
  std::string out = "raycoh-quality.csv";
  std::string image_dir;  // --images: where renders and crops go ("" = <out stem>-images)
  std::vector<Crop> crops;
  Shard shard;  // --shard I/N: only this shard's scene x generator units (records/shard.h); join with raycoh merge
  Denoiser denoise = Denoiser::None;  // --denoise none|oidn: every figure on the denoised renders too
  // For commands built on quality (`raycoh tune`), not options: called with every row of a scene in generator
  // order, measured or resumed; returning true leaves the scene's later generators unmeasured. The console tables
  // are printed only when `console` (they need every row).
  std::function<bool(const QualityRow&)> after_row;
  bool console = true;
};
int run_quality(const QualityOptions& options, const Provenance& provenance);

}  // namespace raycoh
