// Image error metrics of a test image against a reference (docs/design.md section 5).
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
//
// Metric space (MetricSpace, `--metrics` of quality and converge): psnr and ssim above are the TONE-MAPPED choice
// (the default, "tonemapped"). With "linear" (the paper's protocol: no tone map) both are computed on the linear
// radiance instead: PSNR = 10 log10(kPsnrPeak^2 / MSE) with MSE the linear MSE above and the fixed peak 1.0 (linear
// radiance has no natural peak; a fixed one keeps PSNR comparable between scenes and runs, and a PSNR difference
// between two methods is the same for any peak), SSIM on the Rec. 709 luma of the linear values, not clamped, with
// L = 1. mse, rmse and rel_mse are linear in both spaces.
//
// Structure and noise (quality's columns, results/README.md):
//   box_downsample    mean of each k x k block (the image cropped to whole blocks). White noise loses ~k^2 of its
//                     MSE per k; noise correlated over blocks of k pixels or more keeps it, so rel_mse of the
//                     2x/4x/8x downsampled images shows visible blotches and blocks that whole-image error hides.
//   reference_noise   how much MSE the noise of a reference adds to every error against it, from two independent
//                     half-references A and B (mean of the first and of the second half of its frame blocks,
//                     full = (A + B) / 2): E|A - B|^2 = 2 Var(A) = 4 Var(full), so noise = mean |A - B|^2 / 4
//                     (same means over pixels and channels as mse, rel_mse and the metric space's PSNR MSE).
//                     B = 2 full - A (exact when both halves have the same finite sample count per pixel).
//   BiasSamples/bias_test  per-pixel bias of a method: luma of the mean of independent frames minus the
//                     reference's, with a 95% band from the frames' spread (and the reference's own noise).
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

enum class MetricSpace { ToneMapped, Linear };
// "tonemapped" | "linear"; throws raycoh::Error naming `option` and the valid choices.
MetricSpace parse_metric_space(const std::string& option, const std::string& text);
const char* metric_space_name(MetricSpace space);

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
double psnr(const Image& test, const Image& ref, const ToneMap& tm = {}, MetricSpace space = MetricSpace::ToneMapped);
double ssim(const Image& test, const Image& ref, const ToneMap& tm = {}, MetricSpace space = MetricSpace::ToneMapped);
// The SSIM core on single-channel images (row-major, width * height values in [0, data_range]).
double ssim_gray(const std::vector<double>& a, const std::vector<double>& b, int width, int height,
                 double data_range = 1.0);
double luma709(Vec3 c);

ErrorMetrics compare_images(const Image& test, const Image& ref, const ToneMap& tm = {},
                            MetricSpace space = MetricSpace::ToneMapped);

// Mean of each factor x factor block; (width / factor) x (height / factor). Throws unless 1 <= factor <= size.
Image box_downsample(const Image& image, int factor);

// The reference's own noise (see above): the MSE it adds to an error figure in each of the ways they are computed.
struct ReferenceNoise {
  double mse = 0;         // linear
  double rel_mse = 0;     // as rel_mse, against the full reference
  double metric_mse = 0;  // the MSE that PSNR uses in the metric space (display values when tone-mapped)
  // Standard errors of the three estimates (spread of the per-pixel terms / sqrt(pixels); the halves' noise is
  // independent between pixels for a NoOpt reference): what is left of the reference's noise in a figure once the
  // estimate is subtracted.
  double mse_se = 0, rel_mse_se = 0, metric_mse_se = 0;
};
ReferenceNoise reference_noise(const Image& full, const Image& first_half, const ToneMap& tm = {},
                               MetricSpace space = MetricSpace::ToneMapped);
// An error figure with the reference's noise taken out (not below 0; NaN stays NaN).
double minus_noise(double error, double noise);
// Error figures measured against a noisy reference (linear mse, rel_mse, and metric_mse: the MSE that PSNR uses in
// the metric space), with the reference's noise taken out, and the noise's share: the largest of noise / figure
// over the three (1 when a figure is 0 and the noise is not, 0 when both are). One definition for quality and
// converge.
// residual_share: the largest of the estimates' standard error / figure, the share of a corrected figure that is
// still the reference's noise (the uncertainty of the subtraction).
struct NoiseCorrected {
  double share = 0, mse = 0, rel_mse = 0, psnr = 0, residual_share = 0;
};
NoiseCorrected correct_for_noise(const ReferenceNoise& noise, double mse, double rel_mse, double metric_mse);

// Rec. 709 luma of each pixel's mean in the accumulator (NaN where it has no finite sample).
std::vector<double> frame_luma(const Accumulator& frame);
// Mean of each factor x factor block of a width x height luma image (cropped to whole blocks, as box_downsample);
// NaN for a block with a NaN pixel. Throws unless 1 <= factor <= both sizes.
std::vector<double> box_downsample_luma(const std::vector<double>& luma, int width, int height, int factor);

// Per-pixel luma of independent frames (one sample per pixel each), for bias_test.
struct BiasSamples {
  BiasSamples(int width, int height);
  // One frame (its accumulator holds that frame's samples only). Pixels without a finite sample are skipped.
  void add_frame(const Accumulator& frame);

  // One frame's luma per pixel (no finite sample: NaN), e.g. synthetic data in tests.
  void add_luma(const std::vector<double>& luma);
  int frames() const { return static_cast<int>(frame_means.size()); }

  int width, height;
  // Per pixel, of u = luma - shift (shift: the pixel's first finite luma, so that the central moments do not lose
  // their digits to a large mean): sums of u, u^2, u^3.
  std::vector<double> shift, sum, sum2, sum3;
  std::vector<uint32_t> count;      // per pixel: frames with a finite sample
  std::vector<double> frame_means;  // per frame: its image-mean luma over pixels with a finite sample
};

// Bias of the mean of the frames in BiasSamples against a reference (all on Rec. 709 luma of linear radiance).
//   per pixel: d = mean - ref, sigma = sqrt(s^2 / n + v_ref) with s^2 the frames' sample variance of the pixel and
//     v_ref the reference's noise variance (|A - B|^2 / 4 from the halves, averaged over the 3 x 3 neighbourhood to
//     steady a one-pair estimate; 0 without a half image); z = d / sigma, and the pixel's 95% band d +- t(0.975,
//     n - 1) sigma excludes zero when |z| > t(0.975, n - 1).
//   excluded_fraction: the share of tested pixels (n >= 2) whose band excludes zero. It is the false-alarm rate of
//     a per-pixel Student t test, which is 5% only when d is normal. Path-traced pixels are not: their samples are
//     skewed (most paths miss the bright light, a few find it) and heavy-tailed, and with n = R x frames samples
//     the mean keeps a skewness of about gamma / sqrt(n) (gamma the samples' skewness). A pixel whose bright paths
//     were rarely drawn has a mean below the truth AND a small s^2, so the lower tail of z is long (too many
//     exclusions, e.g. 7-8% for lognormal samples of sigma 1 at n = 128, tests/image_error_test.cpp); a pixel whose
//     error is one dominating sample has z near +-1 (too few). The reference's term adds its own estimate's noise.
//     So an unbiased method's share is not 5% but a property of the scene's per-pixel distributions: compare
//     methods with each other (NoOpt's share is the scene's false-alarm rate: every unbiased method whose
//     per-pixel samples are distributed as NoOpt's, which reuse keeps, shares it), or use excluded_skew.
//   excluded_dark, excluded_bright: excluded_fraction split by the sign of d (z below -t, above +t); 2.5% each for
//     normal d. Rare bright paths make an unbiased method's excess dark (and its bright share small): a dark excess
//     with a bright deficit is that skewness; a bias shows as an excess on one side without the other's deficit.
//   quality's bias_excluded_ds4 is excluded_fraction of the same test on 4 x 4 box-downsampled frames and reference
//     (BiasSamples of the frames' block-mean luma): each block's mean holds 16 x more samples, so the mean's
//     skewness is 4 x smaller; the frames stay independent, so it holds for methods whose errors are correlated
//     between pixels too. It is nearer 5% when the skewness is visible in the samples (synthetic lognormal and
//     rare-event pixels), NOT when it comes from paths so rare that most blocks never draw one (fireflies): their
//     missing contribution stays while the visible noise shrinks, so pooling raises the share (cornell noopt, n =
//     128 against a 2048-frame reference: pixels 8.6%, blocks 11.7%; n = 1024: 5.1% and 4.7%).
//   excluded_skew: the same share after Hall's skewness-removing transform of each pixel's statistic (P. Hall,
//     "On the removal of skewness by transformation", JRSS B 54 (1992) 221-228; the monotone form of Johnson's
//     1978 modified t): z_h = z + k z^2 / 3 + k^2 z^3 / 27 + k / 6 with k the estimated skewness of d, k =
//     (m3 / n^2) / sigma^3 (m3 the samples' third central moment; the reference's noise taken as symmetric), the
//     same threshold. It removes the O(1 / sqrt(n)) skewness term of the false-alarm rate, not the heavy tails: on
//     synthetic lognormal samples (sigma 1, n = 128) the plain share is ~7.7%, the corrected one ~6.2%; on normal
//     ones both are 5%.
//   whole image: mean_bias = mean over frames of the frame's image-mean luma minus the reference's image-mean
//     luma, CI half-width t(0.975, frames - 1) * sd / sqrt(frames) (+ the reference's, from v_ref); it holds for
//     methods whose errors are correlated between pixels, since frames are independent, and an image mean of many
//     pixels is close to normal. consistent = |mean_bias| <= ci (a 5% false alarm rate).
//   z2 = mean over pixels of (d / sigma)^2: ~1 for an unbiased method (heavy tails move it either way).
// Throws raycoh::Error on sizes that differ or when there are fewer than 2 frames.
struct BiasReport {
  Image map;  // per pixel (d, sigma, d / sigma) in (R, G, B)
  double excluded_fraction = 0, excluded_dark = 0, excluded_bright = 0, excluded_skew = 0, mean_bias = 0,
         mean_bias_ci = 0, ref_mean = 0, z2 = 0;
  bool consistent = true;
};
BiasReport bias_test(const BiasSamples& samples, const Image& ref, const Image* ref_first_half);
// Two-sided 95% quantile of Student's t with `dof` degrees of freedom (1.96 for large dof).
double t_quantile_975(int dof);
// A display image of a bias map: red where the render is brighter, blue where darker; dim (<= 0.15) where the
// pixel's 95% band includes zero (|z| < 1.96), bright (0.5 at the band's edge, 1 from |z| = 4) where it does not.
Image bias_false_colour(const Image& map);

}  // namespace raycoh
