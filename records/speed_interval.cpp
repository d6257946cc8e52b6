// Median intervals and paired speed-ratio intervals; see speed_interval.h.
#include "records/speed_interval.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace raycoh {
namespace {

constexpr int kBootstrapResamples = 2000;
constexpr uint64_t kBootstrapSeed = 0x5eed'1e55'0f'a11ULL;

// SplitMix64 (Steele, Lea & Flood 2014): a generator simple enough to repeat exactly in any language, so that
// scripts/speed_interval.py recomputes the same intervals from the rows. index(n) = next() mod n.
struct SplitMix64 {
  uint64_t state;
  uint64_t next() {
    uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  size_t index(size_t n) { return static_cast<size_t>(next() % n); }
};

// P(B <= k) for B ~ Binomial(n, 1/2).
double binomial_half_cdf(int n, int k) {
  double p = 0, term = std::pow(0.5, n);  // C(n, 0) / 2^n
  for (int i = 0; i <= k; ++i) {
    p += term;
    term = term * (n - i) / (i + 1);
  }
  return p;
}

double median_of(std::vector<double>& v) {
  const size_t h = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + h, v.end());
  if (v.size() % 2) return v[h];
  const double upper = v[h];
  return 0.5 * (*std::max_element(v.begin(), v.begin() + h) + upper);
}

// Quantile q of sorted values by linear interpolation between neighbours.
double quantile(const std::vector<double>& sorted, double q) {
  const double at = q * double(sorted.size() - 1);
  const size_t i = size_t(at);
  if (i + 1 >= sorted.size()) return sorted.back();
  return sorted[i] + (at - double(i)) * (sorted[i + 1] - sorted[i]);
}

}  // namespace

MedianInterval median_interval(std::vector<double> samples, double confidence) {
  MedianInterval m;
  const int n = static_cast<int>(samples.size());
  if (n == 0) return m;
  std::sort(samples.begin(), samples.end());
  m.median = n % 2 ? samples[n / 2] : 0.5 * (samples[n / 2 - 1] + samples[n / 2]);
  m.lo = samples.front();
  m.hi = samples.back();
  if (n == 1) return m;
  // Largest rank k (1-based) with coverage 1 - 2 P(B <= k-1) >= confidence; k = 1 ([min, max]) when none does.
  int k = 1;
  while (k + 1 <= (n + 1) / 2 && 1.0 - 2.0 * binomial_half_cdf(n, k) >= confidence) ++k;
  m.lo = samples[size_t(k - 1)];
  m.hi = samples[size_t(n - k)];
  m.level = 1.0 - 2.0 * binomial_half_cdf(n, k - 1);
  return m;
}

SpeedRatio speed_ratio(const std::vector<FrameTimes>& base, const std::vector<FrameTimes>& method, double confidence) {
  std::vector<size_t> frames;  // those with a time on both sides
  bool repeated = false;
  for (size_t f = 0; f < std::min(base.size(), method.size()); ++f) {
    if (base[f].times.empty() || method[f].times.empty()) continue;
    frames.push_back(f);
    repeated = repeated || base[f].times.size() > 1 || method[f].times.size() > 1;
  }
  SpeedRatio r;
  if (frames.empty()) return r;
  // The ratio of one (re)sample: frames picked[i], times drawn by `draw` (identity for the point estimate).
  std::vector<double> scratch;
  auto ratio_of = [&](const std::vector<size_t>& picked, auto&& draw) {
    double base_rays = 0, base_t = 0, method_rays = 0, method_t = 0;
    for (size_t f : picked) {
      scratch = draw(base[f].times);
      base_t += median_of(scratch);
      base_rays += base[f].rays;
      scratch = draw(method[f].times);
      method_t += median_of(scratch);
      method_rays += method[f].rays;
    }
    return base_t > 0 && method_t > 0 && base_rays > 0 ? (method_rays / method_t) / (base_rays / base_t) : 0.0;
  };
  r.ratio = ratio_of(frames, [](const std::vector<double>& t) { return t; });
  r.lo = r.hi = r.ratio;
  if (!repeated) return r;
  SplitMix64 rng{kBootstrapSeed};
  auto draw = [&](const std::vector<double>& t) {
    std::vector<double> out(t.size());
    for (double& x : out) x = t[rng.index(t.size())];
    return out;
  };
  std::vector<double> ratios;
  ratios.reserve(kBootstrapResamples);
  std::vector<size_t> picked(frames.size());
  for (int b = 0; b < kBootstrapResamples; ++b) {
    for (size_t& f : picked) f = frames.size() > 1 ? frames[rng.index(frames.size())] : frames.front();
    ratios.push_back(ratio_of(picked, draw));
  }
  std::sort(ratios.begin(), ratios.end());
  r.lo = quantile(ratios, 0.5 * (1.0 - confidence));
  r.hi = quantile(ratios, 0.5 * (1.0 + confidence));
  r.has_interval = true;
  return r;
}

SpeedRatio paired_ratio(const FrameSeries& base, const FrameSeries& method) {
  std::vector<FrameTimes> bs, ms;
  for (const auto& [frame, times] : base)
    if (const auto it = method.find(frame); it != method.end()) {
      bs.push_back(times);
      ms.push_back(it->second);
    }
  return speed_ratio(bs, ms);
}

double series_speed(const FrameSeries& s) {
  double rays = 0, t = 0;
  for (const auto& [frame, f] : s) {
    if (f.times.empty()) continue;
    std::vector<double> v = f.times;
    rays += f.rays;
    t += median_of(v);
  }
  return t > 0 ? rays / t : 0.0;
}

std::string top_of_ranking(const std::vector<std::pair<std::string, const FrameSeries*>>& methods,
                           const FrameSeries& base) {
  if (methods.empty()) return "";
  size_t best = 0;
  for (size_t i = 1; i < methods.size(); ++i)
    if (series_speed(*methods[i].second) > series_speed(*methods[best].second)) best = i;
  const auto& [label, top] = methods[best];
  const SpeedRatio to_base = paired_ratio(base, *top);
  if (!to_base.has_interval)
    return fmt::format("{} highest, {} (no repeated times in the rows: no interval, not called fastest)", label,
                       ratio_text(to_base));
  std::string tied;
  for (size_t i = 0; i < methods.size(); ++i)
    if (i != best && paired_ratio(*methods[i].second, *top).lo <= 1.0)
      tied += fmt::format(", {} {}", methods[i].first,
                          methods[i].second == &base ? "1.00x" : ratio_text(paired_ratio(base, *methods[i].second)));
  // The base itself on top: its ratio to itself is 1 by definition, no interval.
  const std::string top_ratio = top == &base ? "1.00x" : ratio_text(to_base);
  if (tied.empty()) return fmt::format("{} fastest, {}", label, top_ratio);
  return fmt::format("indistinguishable at the top: {} {}{}", label, top_ratio, tied);
}

std::string speed_verdict(const SpeedRatio& r) {
  if (!r.has_interval) return "no interval";
  if (r.lo > 1.0) return "faster";
  if (r.hi < 1.0) return "slower";
  return "indistinguishable";
}

std::string ratio_text(const SpeedRatio& r) {
  if (!r.has_interval) return fmt::format("{:.2f}x", r.ratio);
  return fmt::format("{:.2f}x [{:.2f}, {:.2f}]", r.ratio, r.lo, r.hi);
}

}  // namespace raycoh
