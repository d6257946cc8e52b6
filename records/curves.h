// Error curves of `raycoh converge` read at equal time and at equal error: what its summary rows hold
// (records/converge_row.h).
#pragma once

#include <vector>

namespace raycoh {

// The equal-time / equal-error reading of error curves (public for tests). A curve is a list of (time, error)
// points with increasing time, one per frame.
struct CurvePoint {
  double time = 0, error = 0;
};
// Error at time t, interpolated linearly in (log time, log error) between the frames around t (exact for a
// power law such as error ~ 1/time); NaN before the first frame or after the last.
double error_at_time(const std::vector<CurvePoint>& curve, double t);
// First time the curve reaches error e, interpolated the same way between the last frame above e and the first
// at or below it; the first frame's time if that one is already below; NaN if never reached.
double time_to_error(const std::vector<CurvePoint>& curve, double e);
// A curve against a baseline curve, both on one clock (wall, trace or modeled GPU time: never a sum of two):
//   equal time   T = the shorter of the two curves' last times, the errors at T and their ratio
//                error / baseline_error (< 1: the curve is more accurate in the same time);
//   equal error  E = the larger of the two final errors (both curves reach it), the times to reach it and the
//                speedup baseline_time / time (> 1: the curve reaches it sooner).
struct CurveComparison {
  double horizon = 0, error = 0, baseline_error = 0, equal_time_error_ratio = 0;
  double target_error = 0, time = 0, baseline_time = 0, equal_error_speedup = 0;
};
// Both curves must have at least one point.
CurveComparison compare_curves(const std::vector<CurvePoint>& curve, const std::vector<CurvePoint>& baseline);

}  // namespace raycoh
