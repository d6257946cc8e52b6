// The bias test of shading/metrics.h (BiasSamples, bias_test and its false-colour map): per pixel, whether the
// frames' mean luma is consistent with the reference's, and the whole image's mean bias with its interval.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "shading/metrics.h"

namespace raycoh {

BiasSamples::BiasSamples(int w, int h)
    : width(w),
      height(h),
      shift(static_cast<size_t>(w) * h, 0.0),
      sum(shift.size()),
      sum2(shift.size()),
      sum3(shift.size()),
      count(shift.size()) {}

void BiasSamples::add_luma(const std::vector<double>& luma) {
  RAYCOH_CHECK(luma.size() == sum.size(),
               fmt::format("{} luma values for bias samples of {}x{}", luma.size(), width, height));
  double image_sum = 0;
  size_t finite = 0;
  for (size_t p = 0; p < sum.size(); ++p) {
    const double y = luma[p];
    if (!std::isfinite(y)) continue;
    if (count[p] == 0) shift[p] = y;
    const double u = y - shift[p];
    sum[p] += u;
    sum2[p] += u * u;
    sum3[p] += u * u * u;
    ++count[p];
    image_sum += y;
    ++finite;
  }
  frame_means.push_back(finite > 0 ? image_sum / static_cast<double>(finite) : 0.0);
}

std::vector<double> frame_luma(const Accumulator& frame) {
  const size_t P = static_cast<size_t>(frame.width()) * frame.height();
  std::vector<double> luma(P, std::nan(""));
  const std::vector<double>& sums = frame.sums();
  for (size_t p = 0; p < P; ++p) {
    const uint32_t n = frame.samples(p);
    if (n == 0) continue;
    luma[p] = luma709(Vec3(static_cast<float>(sums[3 * p] / n), static_cast<float>(sums[3 * p + 1] / n),
                           static_cast<float>(sums[3 * p + 2] / n)));
  }
  return luma;
}

std::vector<double> box_downsample_luma(const std::vector<double>& luma, int width, int height, int factor) {
  if (factor < 1 || factor > width || factor > height)
    throw Error(fmt::format("box_downsample_luma: factor {} for a {}x{} image", factor, width, height));
  RAYCOH_CHECK(luma.size() == static_cast<size_t>(width) * height, "box_downsample_luma: size");
  const int w = width / factor, h = height / factor;
  std::vector<double> out(static_cast<size_t>(w) * h, 0.0);
  const double inv = 1.0 / (static_cast<double>(factor) * factor);
  for (int y = 0; y < h * factor; ++y)
    for (int x = 0; x < w * factor; ++x)
      out[static_cast<size_t>(y / factor) * w + x / factor] += luma[static_cast<size_t>(y) * width + x] * inv;
  return out;  // a NaN pixel makes its block NaN
}

void BiasSamples::add_frame(const Accumulator& frame) {
  RAYCOH_CHECK(frame.width() == width && frame.height() == height,
               fmt::format("frame {}x{} for bias samples of {}x{}", frame.width(), frame.height(), width, height));
  add_luma(frame_luma(frame));
}

double t_quantile_975(int dof) {
  static const double table[] = {12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
                                 2.201,  2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
                                 2.080,  2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042};
  if (dof < 1) return std::numeric_limits<double>::infinity();
  if (dof <= 30) return table[dof - 1];
  return 1.959964 + 2.4 / dof;  // within 0.3% of the exact quantile above 30 degrees of freedom
}

BiasReport bias_test(const BiasSamples& s, const Image& ref, const Image* half) {
  if (s.frames() < 2) throw Error(fmt::format("bias test: needs at least 2 frames (got {})", s.frames()));
  if (ref.width != s.width || ref.height != s.height)
    throw Error(
        fmt::format("bias test: frames are {}x{}, the reference is {}x{}", s.width, s.height, ref.width, ref.height));
  if (half) check_same_size(*half, ref);
  const int w = s.width, h = s.height;
  const size_t P = s.sum.size();
  // The reference's noise variance per pixel (luma), from the halves.
  std::vector<double> v_pair(P, 0.0), v_ref(P, 0.0);
  double ref_sum = 0, ref_var_sum = 0;
  for (size_t p = 0; p < P; ++p) {
    const double f = luma709(ref.at(p));
    ref_sum += f;
    if (half) {
      const double a = luma709(half->at(p)), b = 2 * f - a;
      v_pair[p] = std::isfinite(a - b) ? (a - b) * (a - b) / 4 : 0.0;
      ref_var_sum += v_pair[p];
    }
  }
  if (half)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        double sum = 0;
        int n = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
            if (x + dx >= 0 && x + dx < w && y + dy >= 0 && y + dy < h) {
              sum += v_pair[static_cast<size_t>(y + dy) * w + x + dx];
              ++n;
            }
        v_ref[static_cast<size_t>(y) * w + x] = sum / n;
      }
  BiasReport r;
  r.map = Image(w, h);
  size_t excluded = 0, dark = 0, bright = 0, excluded_skew = 0, tested = 0;
  double z2 = 0;
  for (size_t p = 0; p < P; ++p) {
    const uint32_t n = s.count[p];
    if (n < 2) continue;
    const double mu = s.sum[p] / n;  // of u = luma - shift
    const double var = std::max(0.0, (s.sum2[p] - n * mu * mu) / (n - 1));
    const double m3 = s.sum3[p] / n - 3 * mu * s.sum2[p] / n + 2 * mu * mu * mu;  // third central moment
    const double d = s.shift[p] + mu - luma709(ref.at(p)), sigma = std::sqrt(var / n + v_ref[p]);
    if (!std::isfinite(d)) continue;
    const double z = sigma > 0 ? d / sigma : (d == 0 ? 0.0 : std::copysign(1e30, d));
    // Hall's transform (see metrics.h) with k the skewness of d; none where sigma is 0 or the moment is not finite.
    const double k = sigma > 0 && std::isfinite(m3) ? m3 / (static_cast<double>(n) * n) / (sigma * sigma * sigma) : 0.0;
    const double zc = std::clamp(z, -1e6, 1e6);
    const double z_h = zc + k * zc * zc / 3 + k * k * zc * zc * zc / 27 + k / 6;
    const double t = t_quantile_975(static_cast<int>(n) - 1);
    ++tested;
    excluded += std::abs(z) > t;
    dark += z < -t;
    bright += z > t;
    excluded_skew += std::abs(z_h) > t;
    z2 += std::min(z * z, 1e6);
    r.map.set(p, Vec3(static_cast<float>(d), static_cast<float>(sigma), static_cast<float>(z)));
  }
  r.excluded_fraction = tested > 0 ? static_cast<double>(excluded) / tested : std::nan("");
  r.excluded_dark = tested > 0 ? static_cast<double>(dark) / tested : std::nan("");
  r.excluded_bright = tested > 0 ? static_cast<double>(bright) / tested : std::nan("");
  r.excluded_skew = tested > 0 ? static_cast<double>(excluded_skew) / tested : std::nan("");
  r.z2 = tested > 0 ? z2 / tested : std::nan("");
  const int F = s.frames();
  double fm = 0;
  for (double m : s.frame_means) fm += m;
  fm /= F;
  double fv = 0;
  for (double m : s.frame_means) fv += (m - fm) * (m - fm);
  fv /= (F - 1);
  r.ref_mean = ref_sum / static_cast<double>(P);
  r.mean_bias = fm - r.ref_mean;
  // The reference's pixels are independent (NoOpt), so its image mean's variance is the sum over pixels / P^2.
  const double ref_mean_var = ref_var_sum / (static_cast<double>(P) * static_cast<double>(P));
  r.mean_bias_ci = t_quantile_975(F - 1) * std::sqrt(fv / F + ref_mean_var);
  r.consistent = std::abs(r.mean_bias) <= r.mean_bias_ci;
  return r;
}

Image bias_false_colour(const Image& map) {
  Image out(map.width, map.height);
  for (size_t p = 0; p < map.pixels(); ++p) {
    // Inside the band (|z| < 1.96): dim, at most 0.15; outside it: from 0.5 up to 1 at |z| = 4.
    const float z = map.rgb[3 * p + 2], a = std::abs(z);
    const float v = a < 1.96f ? 0.15f * a / 1.96f : std::min(1.f, 0.5f + 0.5f * (a - 1.96f) / 2.04f);
    out.set(p, z > 0 ? Vec3(v, 0.f, 0.f) : Vec3(0.f, 0.f, v));
  }
  return out;
}

}  // namespace raycoh
