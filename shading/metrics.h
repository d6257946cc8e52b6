// Image error metrics of a test image against a reference (DESIGN.md section 5).
//
//   mse, rmse   on the LINEAR (HDR) RGB values, mean over pixels and the three channels.
//   rel_mse     relative MSE, mean over pixels and channels of (t - r)^2 / (r^2 + eps), eps = kRelMseEpsilon
//               = 0.01 (the usual guard for dark pixels, e.g. Rousselle et al. 2011): the standard error
//               measure of Monte Carlo rendering papers, which does not let bright emitters dominate.
//   psnr        10 log10(peak^2 / MSE) on the TONE-MAPPED display image (shading/image.h ToneMap: ACES fit
//               + sRGB OETF by default), peak = kPsnrPeak = 1.0, all three channels. Why tone-mapped: linear
//               radiance has no peak (an emitter of radiance 17 would set it), while display values are bounded
//               by 1, which is the image a reader compares, and what the paper's PSNR table compares. +inf for
//               identical images.
//   ssim        Wang, Bovik, Sheikh, Simoncelli, "Image Quality Assessment: From Error Visibility to Structural
//               Similarity" (IEEE TIP 2004): Gaussian window of 11 taps (sigma 1.5, truncated at 3.5 sigma,
//               normalised), K1 = 0.01, K2 = 0.03, dynamic range L = 1, population (not sample) covariances,
//               borders reflected (half-sample symmetric), the SSIM map averaged over the pixels at least 5 away
//               from every border. Computed on the Rec. 709 luma (0.2126 R' + 0.7152 G' + 0.0722 B') of the
//               tone-mapped, sRGB-encoded image in [0, 1]. These are exactly the choices of scikit-image's
//               structural_similarity(gaussian_weights=True, sigma=1.5, use_sample_covariance=False,
//               data_range=1), which the tests check against. Needs images of at least 11 x 11 pixels:
//               ssim() throws for smaller ones, compare_images() reports NaN.
//   nan_pixels, inf_pixels  pixels with a NaN (or else an Inf) channel in either image. They are left out of
//               mse/rmse/rel_mse/psnr and counted; in SSIM the tone map sends NaN to 0 and +Inf to 1.
//
// Every function throws raycoh::Error when the two images differ in size or are empty.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "shading/image.h"

namespace raycoh {

constexpr double kRelMseEpsilon = 1e-2;
constexpr double kPsnrPeak = 1.0;
constexpr int kSsimWindow = 11;

struct NonFiniteCount {
  uint64_t nan_pixels = 0;  // a NaN in any channel
  uint64_t inf_pixels = 0;  // no NaN, an Inf in some channel
};
NonFiniteCount count_non_finite(const Image& image);

struct ErrorMetrics {
  double mse = 0, rmse = 0, rel_mse = 0, psnr = 0, ssim = 0;
  uint64_t nan_pixels = 0, inf_pixels = 0;  // in either image
  uint64_t pixels_compared = 0;             // pixels finite in both
};

// Throws raycoh::Error naming both sizes unless test and ref have the same, non-zero size.
void check_same_size(const Image& test, const Image& ref);

double mse(const Image& test, const Image& ref);
double rmse(const Image& test, const Image& ref);
double rel_mse(const Image& test, const Image& ref, double eps = kRelMseEpsilon);
double psnr_from_mse(double mse_display, double peak = kPsnrPeak);
double psnr(const Image& test, const Image& ref, const ToneMap& tm = {});
double ssim(const Image& test, const Image& ref, const ToneMap& tm = {});
// The SSIM core on single-channel images (row-major, width * height values in [0, data_range]).
double ssim_gray(const std::vector<double>& a, const std::vector<double>& b, int width, int height,
                 double data_range = 1.0);
double luma709(Vec3 c);

ErrorMetrics compare_images(const Image& test, const Image& ref, const ToneMap& tm = {});

}  // namespace raycoh
