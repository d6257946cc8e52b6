// `raycoh quality`'s measurement of one generator on one scene: R independent renders against the reference
// (harness/image/quality.cpp's header comment defines every figure), and the figures written into its row.
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "generators/generator.h"
#include "harness/image/denoise_eval.h"
#include "harness/image/quality.h"
#include "harness/image/render_common.h"
#include "records/quality_row.h"
#include "shading/metrics.h"
#include "shading/path_tracer.h"

namespace raycoh {

// The error figures of each of R renders (or of their denoised images), one entry per render.
struct PerRender {
  std::vector<double> psnr, ssim, rmse, rel_mse, mse;
  std::vector<double> metric_mse;  // the MSE the PSNR was computed from (in the metric space)
  void add(const ErrorMetrics& e) {
    psnr.push_back(e.psnr);
    ssim.push_back(e.ssim);
    rmse.push_back(e.rmse);
    rel_mse.push_back(e.rel_mse);
    mse.push_back(e.mse);
    metric_mse.push_back(std::pow(10.0, -e.psnr / 10.0) * kPsnrPeak * kPsnrPeak);
  }
};

// The error of the mean of the R renders: MSE, relMSE, and relMSE 8x box-downsampled.
struct OfMean {
  double mse = 0, rel_mse = 0, ds8 = 0;
};

// --denoise: every render's denoised image (empty without a denoiser), its relMSE 8x downsampled, the denoiser's
// seconds.
struct DenoisedRenders {
  PerRender renders;
  std::vector<double> ds8;
  double seconds = 0;
};

// R independent renders of one generator against the reference.
struct Renders {
  PerRender renders;
  std::vector<double> ds[3];  // per render: rel_mse of the 2x/4x/8x images
  OfMean of_mean;
  BiasReport bias;
  double bias_excluded_ds4 = std::nan("");  // bias_test's share on the 4 x 4 box-downsampled frames
  bool has_bias = false;
  FrameStats total;
  uint64_t non_finite_pixels = 0;
  DenoisedRenders denoised;
  // --device cuda: the frames' GPU milliseconds summed (CUDA events), their clock ("measured" | "simulated") and
  // the device's name; 0 and empty on the CPU.
  double gpu_ms = 0;
  std::string gpu_clock, device_name;
};

// Where a generator's renders are written: render 0 and its crops, tone-mapped for display.
struct ImageSink {
  std::string dir, base;  // base: "<scene>-<generator>"
  const std::vector<Crop>& crops;
  std::string hdr_dir = "";  // non-empty: every render's linear image also goes there as r<i>.exr, for HDR-FLIP
  std::string hdr_path(int r) const { return (std::filesystem::path(hdr_dir) / fmt::format("r{}.exr", r)).string(); }
  std::string main_path() const { return (std::filesystem::path(dir) / (base + display_extension())).string(); }
  void write(const Image& img, const ToneMap& tm) const {
    write_image(img, main_path(), tm);
    for (size_t ci = 0; ci < crops.size(); ++ci)
      write_image(crop(img, crops[ci]),
                  (std::filesystem::path(dir) / fmt::format("{}-crop{}{}", base, ci, display_extension())).string(),
                  tm);
  }
  // The bias map: signed false colour (display) and, in a build with EXR, (d, sigma, z) as float.
  void write_bias(const BiasReport& b) const {
    write_image(bias_false_colour(b.map),
                (std::filesystem::path(dir) / (base + "-bias" + display_extension())).string(),
                ToneMap{ToneMapKind::Clamp, 1.f, false});
    if (image_io_available()) write_image(b.map, (std::filesystem::path(dir) / (base + "-bias.exr")).string());
  }
};

// With an active denoiser, each render is also denoised (with its first hits' albedo and normal, which go to the
// sink's folder as <base>-albedo and <base>-normal float images for render 0) and render 0's denoised image and
// crops are written as <base>-denoised.
Renders render_generator(const QualityOptions& o, const LoadedScene& ls, Generator& generator, const std::string& label,
                         const ReferenceImage& ref, const ToneMap& tm, const ImageSink& sink, size_t item, size_t items,
                         const DenoiseEval& denoiser);
// The figures of the renders (R of them, each of `frames` frames) into the row; noise: the reference's own.
void fill_measurements(QualityRow& row, const Renders& m, int R, int frames, const ReferenceNoise* noise);
// The denoised figures (means over the renders, as the raw ones); nothing when the renders were not denoised.
void fill_denoised(QualityRow& row, const Renders& m, const ReferenceNoise* noise);

}  // namespace raycoh
