// Error metrics (definitions and the papers they follow in metrics.h). Sums run in double over pixels in a
// fixed order, so a metric is the same number whatever the thread count.
#include "shading/metrics.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace raycoh {

namespace {

bool finite_pixel(const Image& img, size_t p) { return is_finite(img.at(p)); }

// Sums per_channel(t, r) over the channels of the pixels finite in both images; counted = those pixels.
template <typename F>
double sum_over_finite(const Image& test, const Image& ref, F&& per_channel, uint64_t& counted) {
  double sum = 0;
  counted = 0;
  for (size_t p = 0; p < test.pixels(); ++p) {
    if (!finite_pixel(test, p) || !finite_pixel(ref, p)) continue;
    ++counted;
    for (int c = 0; c < 3; ++c) sum += per_channel(test.rgb[3 * p + c], ref.rgb[3 * p + c]);
  }
  return sum;
}

double mean_over_channels(double sum, uint64_t pixels) {
  return pixels > 0 ? sum / (3.0 * static_cast<double>(pixels)) : std::numeric_limits<double>::quiet_NaN();
}

// The 11-tap Gaussian of Wang et al. (sigma 1.5), normalised, as scipy.ndimage builds it.
std::array<double, kSsimWindow> gaussian_taps() {
  std::array<double, kSsimWindow> w{};
  const double sigma = 1.5;
  double sum = 0;
  for (int i = 0; i < kSsimWindow; ++i) {
    const double x = i - kSsimWindow / 2;
    w[i] = std::exp(-0.5 * x * x / (sigma * sigma));
    sum += w[i];
  }
  for (double& v : w) v /= sum;
  return w;
}

// Half-sample symmetric reflection (d c b a | a b c d | d c b a), valid for overshoots up to n.
int reflect(int i, int n) { return i < 0 ? -i - 1 : (i >= n ? 2 * n - i - 1 : i); }

// Separable Gaussian filter with reflected borders: along y first, then x.
std::vector<double> gaussian_filter(const std::vector<double>& in, int w, int h) {
  static const std::array<double, kSsimWindow> taps = gaussian_taps();
  const int r = kSsimWindow / 2;
  std::vector<double> tmp(in.size()), out(in.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double s = 0;
      for (int k = -r; k <= r; ++k) s += taps[k + r] * in[static_cast<size_t>(reflect(y + k, h)) * w + x];
      tmp[static_cast<size_t>(y) * w + x] = s;
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double s = 0;
      for (int k = -r; k <= r; ++k) s += taps[k + r] * tmp[static_cast<size_t>(y) * w + reflect(x + k, w)];
      out[static_cast<size_t>(y) * w + x] = s;
    }
  return out;
}

// One channel value as the metric space's PSNR sees it.
float metric_value(float v, const ToneMap& tm, MetricSpace space) {
  return space == MetricSpace::Linear ? v : tone_map_channel(v, tm);
}

std::vector<double> metric_luma(const Image& img, const ToneMap& tm, MetricSpace space) {
  std::vector<double> y(img.pixels());
  for (size_t p = 0; p < img.pixels(); ++p) {
    const Vec3 c = img.at(p);
    y[p] = luma709({metric_value(c.x, tm, space), metric_value(c.y, tm, space), metric_value(c.z, tm, space)});
  }
  return y;
}

}  // namespace

MetricSpace parse_metric_space(const std::string& option, const std::string& text) {
  if (text == "tonemapped") return MetricSpace::ToneMapped;
  if (text == "linear") return MetricSpace::Linear;
  throw Error(fmt::format("{} '{}': expected tonemapped or linear", option, text));
}

const char* metric_space_name(MetricSpace space) { return space == MetricSpace::Linear ? "linear" : "tonemapped"; }

double luma709(Vec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

NonFiniteCount count_non_finite(const Image& image) {
  NonFiniteCount n;
  for (size_t p = 0; p < image.pixels(); ++p) {
    const Vec3 c = image.at(p);
    if (std::isnan(c.x) || std::isnan(c.y) || std::isnan(c.z))
      ++n.nan_pixels;
    else if (!is_finite(c))
      ++n.inf_pixels;
  }
  return n;
}

void check_same_size(const Image& test, const Image& ref) {
  if (test.width != ref.width || test.height != ref.height)
    throw Error(fmt::format("image sizes differ: test image is {}x{}, reference is {}x{}", test.width, test.height,
                            ref.width, ref.height));
  if (test.empty()) throw Error("cannot compare empty images (0 pixels)");
}

double mse(const Image& test, const Image& ref) {
  check_same_size(test, ref);
  uint64_t n;
  const double s = sum_over_finite(
      test, ref, [](double t, double r) { return (t - r) * (t - r); }, n);
  return mean_over_channels(s, n);
}

double rmse(const Image& test, const Image& ref) { return std::sqrt(mse(test, ref)); }

double rel_mse(const Image& test, const Image& ref, double eps) {
  check_same_size(test, ref);
  uint64_t n;
  const double s = sum_over_finite(
      test, ref, [eps](double t, double r) { return (t - r) * (t - r) / (r * r + eps); }, n);
  return mean_over_channels(s, n);
}

double psnr_from_mse(double mse_display, double peak) {
  if (std::isnan(mse_display)) return mse_display;
  if (mse_display <= 0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(peak * peak / mse_display);
}

double psnr(const Image& test, const Image& ref, const ToneMap& tm, MetricSpace space) {
  check_same_size(test, ref);
  uint64_t n;
  const double s = sum_over_finite(
      test, ref,
      [&tm, space](double t, double r) {
        const double d = static_cast<double>(metric_value(static_cast<float>(t), tm, space)) -
                         metric_value(static_cast<float>(r), tm, space);
        return d * d;
      },
      n);
  return psnr_from_mse(mean_over_channels(s, n));
}

double ssim_gray(const std::vector<double>& a, const std::vector<double>& b, int width, int height, double data_range) {
  if (width < kSsimWindow || height < kSsimWindow)
    throw Error(fmt::format("SSIM needs images of at least {0}x{0} pixels (Gaussian window of {0} taps); got {1}x{2}",
                            kSsimWindow, width, height));
  const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
  RAYCOH_CHECK(a.size() == n && b.size() == n,
               fmt::format("{} and {} values for {}x{}", a.size(), b.size(), width, height));
  std::vector<double> aa(n), bb(n), ab(n);
  for (size_t i = 0; i < n; ++i) {
    aa[i] = a[i] * a[i];
    bb[i] = b[i] * b[i];
    ab[i] = a[i] * b[i];
  }
  const std::vector<double> ux = gaussian_filter(a, width, height), uy = gaussian_filter(b, width, height),
                            uxx = gaussian_filter(aa, width, height), uyy = gaussian_filter(bb, width, height),
                            uxy = gaussian_filter(ab, width, height);
  const double c1 = (0.01 * data_range) * (0.01 * data_range), c2 = (0.03 * data_range) * (0.03 * data_range);
  const int pad = kSsimWindow / 2;
  double sum = 0;
  for (int y = pad; y < height - pad; ++y)
    for (int x = pad; x < width - pad; ++x) {
      const size_t i = static_cast<size_t>(y) * width + x;
      const double vx = uxx[i] - ux[i] * ux[i], vy = uyy[i] - uy[i] * uy[i], vxy = uxy[i] - ux[i] * uy[i];
      sum += ((2 * ux[i] * uy[i] + c1) * (2 * vxy + c2)) / ((ux[i] * ux[i] + uy[i] * uy[i] + c1) * (vx + vy + c2));
    }
  return sum / (static_cast<double>(width - 2 * pad) * static_cast<double>(height - 2 * pad));
}

double ssim(const Image& test, const Image& ref, const ToneMap& tm, MetricSpace space) {
  check_same_size(test, ref);
  return ssim_gray(metric_luma(test, tm, space), metric_luma(ref, tm, space), test.width, test.height, 1.0);
}

ErrorMetrics compare_images(const Image& test, const Image& ref, const ToneMap& tm, MetricSpace space) {
  check_same_size(test, ref);
  ErrorMetrics m;
  uint64_t n = 0;
  const double sum = sum_over_finite(
      test, ref, [](double t, double r) { return (t - r) * (t - r); }, n);
  m.mse = mean_over_channels(sum, n);
  m.pixels_compared = n;
  m.rmse = std::sqrt(m.mse);
  m.rel_mse = rel_mse(test, ref);
  m.psnr = psnr(test, ref, tm, space);
  m.ssim = test.width >= kSsimWindow && test.height >= kSsimWindow ? ssim(test, ref, tm, space) : std::nan("");
  for (size_t p = 0; p < test.pixels(); ++p) {
    const Vec3 t = test.at(p), r = ref.at(p);
    const bool nan =
        std::isnan(t.x) || std::isnan(t.y) || std::isnan(t.z) || std::isnan(r.x) || std::isnan(r.y) || std::isnan(r.z);
    if (nan)
      ++m.nan_pixels;
    else if (!is_finite(t) || !is_finite(r))
      ++m.inf_pixels;
  }
  return m;
}

Image box_downsample(const Image& image, int factor) {
  if (factor < 1 || factor > image.width || factor > image.height)
    throw Error(fmt::format("box downsample by {}: must be in [1, {}] for a {}x{} image", factor,
                            std::min(image.width, image.height), image.width, image.height));
  Image out(image.width / factor, image.height / factor);
  const double inv = 1.0 / (static_cast<double>(factor) * factor);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      double s[3] = {0, 0, 0};
      for (int dy = 0; dy < factor; ++dy)
        for (int dx = 0; dx < factor; ++dx) {
          const Vec3 c = image.at(x * factor + dx, y * factor + dy);
          s[0] += c.x;
          s[1] += c.y;
          s[2] += c.z;
        }
      out.set(x, y,
              Vec3(static_cast<float>(s[0] * inv), static_cast<float>(s[1] * inv), static_cast<float>(s[2] * inv)));
    }
  return out;
}

ReferenceNoise reference_noise(const Image& full, const Image& first_half, const ToneMap& tm, MetricSpace space) {
  check_same_size(first_half, full);
  // Per-pixel terms (mean over the channels) and their squares, for the means and their standard errors.
  double s[3] = {0, 0, 0}, s2[3] = {0, 0, 0};
  uint64_t n = 0;
  for (size_t p = 0; p < full.pixels(); ++p) {
    if (!finite_pixel(full, p) || !finite_pixel(first_half, p)) continue;
    ++n;
    double q[3] = {0, 0, 0};
    for (int c = 0; c < 3; ++c) {
      const double f = full.rgb[3 * p + c], a = first_half.rgb[3 * p + c], b = 2 * f - a;
      const double d2 = (a - b) * (a - b) / 4;
      q[0] += d2 / 3;
      q[1] += d2 / (f * f + kRelMseEpsilon) / 3;
      const double dm = metric_value(static_cast<float>(a), tm, space) - metric_value(static_cast<float>(b), tm, space);
      q[2] += dm * dm / 4 / 3;
    }
    for (int k = 0; k < 3; ++k) {
      s[k] += q[k];
      s2[k] += q[k] * q[k];
    }
  }
  if (n == 0) return {std::nan(""), std::nan(""), std::nan(""), std::nan(""), std::nan(""), std::nan("")};
  double mean[3], se[3];
  for (int k = 0; k < 3; ++k) {
    mean[k] = s[k] / static_cast<double>(n);
    const double var = n > 1 ? std::max(0.0, (s2[k] - n * mean[k] * mean[k]) / static_cast<double>(n - 1)) : 0.0;
    se[k] = std::sqrt(var / static_cast<double>(n));
  }
  return {mean[0], mean[1], mean[2], se[0], se[1], se[2]};
}

double minus_noise(double error, double noise) {
  return std::isnan(error) ? error : std::max(0.0, error - noise);  // an undefined figure stays undefined
}

NoiseCorrected correct_for_noise(const ReferenceNoise& noise, double mse, double rel_mse, double metric_mse) {
  auto share = [](double n, double e) { return e > 0 ? n / e : (n > 0 ? 1.0 : 0.0); };
  NoiseCorrected c;
  c.share = std::max({share(noise.mse, mse), share(noise.rel_mse, rel_mse), share(noise.metric_mse, metric_mse)});
  c.residual_share =
      std::max({share(noise.mse_se, mse), share(noise.rel_mse_se, rel_mse), share(noise.metric_mse_se, metric_mse)});
  c.mse = minus_noise(mse, noise.mse);
  c.rel_mse = minus_noise(rel_mse, noise.rel_mse);
  c.psnr = psnr_from_mse(minus_noise(metric_mse, noise.metric_mse));
  return c;
}

}  // namespace raycoh
