#include "harness/tune/tune_select.h"

#include <fmt/format.h>

#include <algorithm>

#include "shading/metrics.h"

namespace raycoh {

namespace {

constexpr double kBiasShareZ = 3.09;  // one-sided 0.1%

struct Bound {
  const char* name;
  double limit;
  const RatioStat* stat;
};

std::vector<Bound> bounds_of(const TuneCandidate& c, const TuneBudget& b) {
  std::vector<Bound> out;
  // A `paper` bound that could not be resolved is NaN: it stays in, and no setting meets it.
  if (b.ds8 > 0 || std::isnan(b.ds8)) out.push_back({"ds8", b.ds8, &c.ds8});
  if (b.rel > 0 || std::isnan(b.rel)) out.push_back({"rel", b.rel, &c.rel});
  if (b.flip > 0 || std::isnan(b.flip)) out.push_back({"flip", b.flip, &c.flip});
  return out;
}

}  // namespace

RatioStat paired_ratio(const std::vector<double>& x, const std::vector<double>& base) {
  std::vector<double> logs;
  for (size_t i = 0; i < std::min(x.size(), base.size()); ++i)
    if (std::isfinite(x[i]) && std::isfinite(base[i]) && x[i] > 0 && base[i] > 0)
      logs.push_back(std::log(x[i] / base[i]));
  RatioStat s;
  s.n = static_cast<int>(logs.size());
  if (logs.empty()) return s;
  double sum = 0;
  for (double v : logs) sum += v;
  const double mean = sum / s.n;
  s.mean = std::exp(mean);
  if (s.n == 1) {
    s.lo = s.hi = s.mean;
    return s;
  }
  double ss = 0;
  for (double v : logs) ss += (v - mean) * (v - mean);
  const double half = t_quantile_975(s.n - 1) * std::sqrt(ss / (s.n - 1) / s.n);
  s.lo = std::exp(mean - half);
  s.hi = std::exp(mean + half);
  return s;
}

TuneVerdict judge(const TuneCandidate& c, const TuneBudget& b) {
  TuneVerdict v;
  if (!c.error_measured) {
    v.reason = "error not measured";
    return v;
  }
  std::vector<std::string> why;
  v.excess = 0;
  for (const Bound& bound : bounds_of(c, b)) {
    const RatioStat& s = *bound.stat;
    if (s.n == 0 || std::isnan(bound.limit)) {
      v.excess = INFINITY;
      why.push_back(std::string(bound.name) + (s.n == 0 ? " not measured" : ": the paper's default not measured"));
      continue;
    }
    v.excess = std::max(v.excess, s.hi / bound.limit);
    if (s.hi > bound.limit)
      why.push_back(fmt::format("{} {:.3f} [{:.3f}, {:.3f}] > {:.4g}", bound.name, s.mean, s.lo, s.hi, bound.limit));
  }
  if (b.no_bias) {
    const double z = bias_share_z(c);
    if (c.bias_verdict != "consistent")
      why.push_back(c.bias_verdict.empty() ? "bias not tested" : "bias: the whole image's mean is " + c.bias_verdict);
    else if (z > kBiasShareZ)
      why.push_back(fmt::format("bias: {:.1f}% of pixels exclude zero, noopt {:.1f}% (z {:.1f})", 100 * c.bias_share,
                                100 * c.noopt_bias_share, z));
    v.bias_rejected = c.bias_verdict != "consistent" || z > kBiasShareZ;
  }
  v.pass = why.empty();
  for (size_t i = 0; i < why.size(); ++i) v.reason += (i ? "; " : "") + why[i];
  return v;
}

TuneBudget resolve_paper(const TuneBudget& b, const TuneCandidate* paper) {
  TuneBudget r = b;
  const bool measured = paper && paper->error_measured;
  auto bound = [&](bool is_paper, double value, const RatioStat& s) {
    return !is_paper ? value : measured && std::isfinite(s.hi) ? std::max(1.0, s.hi) : NAN;
  };
  r.ds8 = bound(b.ds8_paper, b.ds8, measured ? paper->ds8 : RatioStat{});
  r.rel = bound(b.rel_paper, b.rel, measured ? paper->rel : RatioStat{});
  r.flip = bound(b.flip_paper, b.flip, measured ? paper->flip : RatioStat{});
  return r;
}

void settle_speed(TuneChoice& ch, const std::vector<TuneCandidate>& cs, int paper) {
  ch.fastest_passing = ch.recommended;
  ch.speed_call.clear();
  if (ch.recommended < 0 || paper < 0 || ch.recommended == paper) return;
  ch.speed_call = speed_verdict(cs[static_cast<size_t>(ch.recommended)].to_paper);
  const bool not_faster = ch.speed_call == "indistinguishable" || ch.speed_call == "slower";
  if (not_faster && ch.verdicts[static_cast<size_t>(paper)].pass) ch.recommended = paper;
}

double bias_share_z(const TuneCandidate& c) {
  const double p1 = c.bias_share, p0 = c.noopt_bias_share;
  if (!std::isfinite(p1) || !std::isfinite(p0) || c.share_units <= 0 || c.noopt_units <= 0) return std::nan("");
  const double se = std::sqrt(p1 * (1 - p1) / c.share_units + p0 * (1 - p0) / c.noopt_units);
  return se > 0 ? (p1 - p0) / se : std::nan("");
}

double axis_value(const TuneCandidate& c, const std::string& axis) {
  return axis == "ds8" ? c.ds8.mean : axis == "rel" ? c.rel.mean : c.flip.mean;
}

TuneChoice choose(const std::vector<TuneCandidate>& cs, const TuneBudget& b) {
  TuneChoice out;
  out.error_axis = b.ds8 > 0 || std::isnan(b.ds8) ? "ds8" : b.rel > 0 || std::isnan(b.rel) ? "rel" : "flip";
  for (const TuneCandidate& c : cs) out.verdicts.push_back(judge(c, b));
  out.front.assign(cs.size(), false);
  for (size_t i = 0; i < cs.size(); ++i) {
    const double ei = axis_value(cs[i], out.error_axis);
    if (!cs[i].error_measured || !std::isfinite(ei)) continue;
    bool dominated = false;
    for (size_t j = 0; j < cs.size() && !dominated; ++j) {
      const double ej = axis_value(cs[j], out.error_axis);
      if (j == i || !cs[j].error_measured || !std::isfinite(ej)) continue;
      dominated = cs[j].speed >= cs[i].speed && ej <= ei && (cs[j].speed > cs[i].speed || ej < ei);
    }
    out.front[i] = !dominated;
  }
  for (size_t i = 0; i < cs.size(); ++i)
    if (out.verdicts[i].pass && (out.recommended < 0 || cs[i].speed > cs[static_cast<size_t>(out.recommended)].speed))
      out.recommended = static_cast<int>(i);
  if (out.recommended >= 0) return out;
  bool any_accepted = false;
  for (size_t i = 0; i < cs.size(); ++i) any_accepted |= cs[i].error_measured && !out.verdicts[i].bias_rejected;
  for (size_t i = 0; i < cs.size(); ++i) {
    if (!cs[i].error_measured || (any_accepted && out.verdicts[i].bias_rejected)) continue;
    const int m = out.closest_miss;
    if (m < 0 || out.verdicts[i].excess < out.verdicts[static_cast<size_t>(m)].excess)
      out.closest_miss = static_cast<int>(i);
  }
  return out;
}

}  // namespace raycoh
