#include "records/curves.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace raycoh {

namespace {

// Log when both values are positive (the usual case), else the value itself, so that interpolation degrades to
// linear for zero errors or times.
double lg(double v, bool use_log) { return use_log ? std::log(v) : v; }

}  // namespace

double error_at_time(const std::vector<CurvePoint>& c, double t) {
  if (c.empty() || !(t >= c.front().time) || !(t <= c.back().time)) return std::nan("");
  for (size_t k = 0; k + 1 < c.size(); ++k) {
    if (t > c[k + 1].time) continue;
    const CurvePoint& a = c[k];
    const CurvePoint& b = c[k + 1];
    if (!(b.time > a.time)) return b.error;
    const bool log_t = a.time > 0, log_e = a.error > 0 && b.error > 0;
    const double f = (lg(t, log_t) - lg(a.time, log_t)) / (lg(b.time, log_t) - lg(a.time, log_t));
    const double v = lg(a.error, log_e) + f * (lg(b.error, log_e) - lg(a.error, log_e));
    return log_e ? std::exp(v) : v;
  }
  return c.back().error;
}

double time_to_error(const std::vector<CurvePoint>& c, double e) {
  for (size_t k = 0; k < c.size(); ++k) {
    if (!(c[k].error <= e)) continue;
    if (k == 0) return c[0].time;
    const CurvePoint& a = c[k - 1];
    const CurvePoint& b = c[k];
    const bool log_t = a.time > 0, log_e = b.error > 0 && e > 0;
    double f = 1.0;
    if (lg(a.error, log_e) != lg(b.error, log_e))
      f = (lg(a.error, log_e) - lg(e, log_e)) / (lg(a.error, log_e) - lg(b.error, log_e));
    const double v = lg(a.time, log_t) + std::clamp(f, 0.0, 1.0) * (lg(b.time, log_t) - lg(a.time, log_t));
    return log_t ? std::exp(v) : v;
  }
  return std::nan("");
}

CurveComparison compare_curves(const std::vector<CurvePoint>& c, const std::vector<CurvePoint>& b) {
  RAYCOH_CHECK(!c.empty() && !b.empty(), "compare_curves: an empty curve");
  CurveComparison r;
  r.horizon = std::min(c.back().time, b.back().time);
  r.error = error_at_time(c, r.horizon);
  r.baseline_error = error_at_time(b, r.horizon);
  r.equal_time_error_ratio = r.error / r.baseline_error;
  r.target_error = std::max(c.back().error, b.back().error);
  r.time = time_to_error(c, r.target_error);
  r.baseline_time = time_to_error(b, r.target_error);
  r.equal_error_speedup = r.baseline_time / r.time;
  return r;
}

}  // namespace raycoh
