#include "harness/image/quality_measure.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <optional>

#include "harness/common/progress.h"
#include "harness/image/frame_source.h"
#include "harness/image/quality.h"
#include "shading/reference.h"

namespace raycoh {

namespace fs = std::filesystem;

namespace {

double mean_of(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

constexpr int kDownsample[3] = {2, 4, 8};

// rel_mse of the factor x factor box-downsampled images; NaN when the image is smaller than a block.
double downsampled_rel_mse(const Image& img, const Image& ref, int factor) {
  if (img.width < factor || img.height < factor) return std::nan("");
  return rel_mse(box_downsample(img, factor), box_downsample(ref, factor));
}

// Render r's denoised image into m (its figures) and, for render 0, the sink's folder (with the auxiliary images).
void add_denoised(Renders& m, const DenoiseEval& dn, const Image& img, const AuxAccumulators& aux, int r,
                  const ReferenceImage& ref, const ToneMap& tm, MetricSpace space, const ImageSink& sink) {
  double seconds = 0;
  const Image d = dn.denoise(img, aux, &seconds);
  m.denoised.seconds += seconds;
  m.denoised.renders.add(compare_images(d, ref.image, tm, space));
  m.denoised.ds8.push_back(downsampled_rel_mse(d, ref.image, 8));
  if (r != 0) return;
  ImageSink{sink.dir, sink.base + "-denoised", sink.crops}.write(d, tm);
  const std::string stem = (fs::path(sink.dir) / sink.base).string();
  write_image(aux.albedo.mean(), stem + "-albedo" + float_image_extension());
  write_image(aux.normal.mean(), stem + "-normal" + float_image_extension());
}

}  // namespace

Renders render_generator(const QualityOptions& o, const LoadedScene& ls, Generator& generator, const std::string& label,
                         const ReferenceImage& ref, const ToneMap& tm, const ImageSink& sink, size_t item, size_t items,
                         const DenoiseEval& denoiser) {
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
    FrameSource source(o.common.device, ls, generator, settings_of(o.common, o.common.seed + r));
    out.gpu_clock = source.clock();
    out.device_name = source.device_name();
    Accumulator acc(o.common.width, o.common.height);
    std::optional<AuxAccumulators> aux;  // the first hits' albedo and normal, for the denoiser
    if (denoiser.active()) aux.emplace(o.common.width, o.common.height);
    for (int f = 0; f < o.frames; ++f) {
      Accumulator frame(o.common.width, o.common.height);  // this frame alone, for the bias test's spread
      const SourcedFrame sf = source.render(static_cast<uint32_t>(f), frame, aux ? &*aux : nullptr);
      out.total.add(sf.stats);
      if (source.on_device()) out.gpu_ms += sf.gpu_ms;
      acc.merge(frame);
      const std::vector<double> luma = frame_luma(frame);
      samples.add_luma(luma);
      if (blocks) block_samples.add_luma(box_downsample_luma(luma, o.common.width, o.common.height, kBiasBlock));
      bar.update(item, items, r * o.frames + f, R * o.frames, fmt::format("{} {}", ls.scene.name, label));
    }
    out.non_finite_pixels += acc.pixels_with_non_finite();
    const Image img = acc.mean();
    const ErrorMetrics m = compare_images(img, ref.image, tm, o.common.metrics);
    out.renders.add(m);
    for (int k = 0; k < 3; ++k) out.ds[k].push_back(downsampled_rel_mse(img, ref.image, kDownsample[k]));
    for (size_t p = 0; p < img.pixels(); ++p) mean_acc.add(p, img.at(p));
    if (r == 0) sink.write(img, tm);
    if (!sink.hdr_dir.empty()) write_image(img, sink.hdr_path(r));
    if (aux) add_denoised(out, denoiser, img, *aux, r, ref, tm, o.common.metrics, sink);
  }
  bar.clear();
  const Image mean_image = mean_acc.mean();
  out.of_mean.mse = mse(mean_image, ref.image);
  out.of_mean.rel_mse = rel_mse(mean_image, ref.image);
  out.of_mean.ds8 = downsampled_rel_mse(mean_image, ref.image, 8);
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

void fill_measurements(QualityRow& row, const Renders& m, int R, int frames, const ReferenceNoise* noise) {
  row.psnr = mean_of(m.renders.psnr);
  row.psnr_std = std::nan("");
  if (R > 1) {
    double s2 = 0;
    for (double x : m.renders.psnr) s2 += (x - row.psnr) * (x - row.psnr);
    row.psnr_std = std::sqrt(s2 / (R - 1));
  }
  row.ssim = mean_of(m.renders.ssim);
  row.rmse = mean_of(m.renders.rmse);
  row.rel_mse = mean_of(m.renders.rel_mse);
  row.mse = mean_of(m.renders.mse);
  row.mse_of_mean = m.of_mean.mse;
  row.bias2 = R > 1 ? (R * m.of_mean.mse - row.mse) / (R - 1) : std::nan("");
  row.variance = R > 1 ? (row.mse - m.of_mean.mse) * R / (R - 1) : std::nan("");
  const double nan = std::nan("");
  row.ref_noise_mse = noise ? noise->mse : nan;
  row.ref_noise_rel_mse = noise ? noise->rel_mse : nan;
  const NoiseCorrected corr = noise ? correct_for_noise(*noise, row.mse, row.rel_mse, mean_of(m.renders.metric_mse))
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
  row.rel_mse_renders = m.renders.rel_mse;
  row.rel_mse_ds8_renders = m.ds[2];
  // The variance part alone (as `variance` above, on relMSE): bias, which survives downsampling too, left out.
  row.rel_var = R > 1 ? (row.rel_mse - m.of_mean.rel_mse) * R / (R - 1) : nan;
  row.rel_var_ds8 = R > 1 ? (row.rel_mse_ds8 - m.of_mean.ds8) * R / (R - 1) : nan;
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
  if (!m.gpu_clock.empty()) {  // on the device: its GPU time; trace and generation time not measured apart
    row.gpu_clock = m.gpu_clock;
    row.gpu_frame_ms = m.gpu_ms / (static_cast<double>(R) * frames);
    row.trace_s = nan;
    row.gen_ms = nan;
    row.mray_s = nan;
  }
  row.hybrid_diffuse_share = m.total.generation.rays > 0 ? static_cast<double>(m.total.hybrid_diffuse) /
                                                               static_cast<double>(m.total.generation.rays)
                                                         : nan;
}

void fill_denoised(QualityRow& row, const Renders& m, const ReferenceNoise* noise) {
  if (m.denoised.renders.psnr.empty()) return;
  const size_t R = m.denoised.renders.psnr.size();
  row.denoised_psnr = mean_of(m.denoised.renders.psnr);
  if (R > 1) {
    double s2 = 0;
    for (double x : m.denoised.renders.psnr) s2 += (x - row.denoised_psnr) * (x - row.denoised_psnr);
    row.denoised_psnr_std = std::sqrt(s2 / static_cast<double>(R - 1));
  }
  row.denoised_ssim = mean_of(m.denoised.renders.ssim);
  row.denoised_rmse = mean_of(m.denoised.renders.rmse);
  row.denoised_rel_mse = mean_of(m.denoised.renders.rel_mse);
  row.denoised_mse = mean_of(m.denoised.renders.mse);
  row.denoised_rel_mse_ds8 = mean_of(m.denoised.ds8);
  row.denoise_s = m.denoised.seconds;
  if (noise) {
    const NoiseCorrected c =
        correct_for_noise(*noise, row.denoised_mse, row.denoised_rel_mse, mean_of(m.denoised.renders.metric_mse));
    row.denoised_mse_corr = c.mse;
    row.denoised_rel_mse_corr = c.rel_mse;
    row.denoised_psnr_corr = c.psnr;
  }
}

}  // namespace raycoh
