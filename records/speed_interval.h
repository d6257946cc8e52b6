// Intervals for measured speed: the median of a row's repeated times with a distribution-free confidence interval,
// and the ratio of two methods' speeds with a paired bootstrap interval; the words a table may say of a ratio.
//
// A row's interval (median_interval) comes from order statistics: for n sorted times x(1) <= .. <= x(n), the
// interval [x(k), x(n+1-k)] holds the true median with probability 1 - 2 P(B <= k-1), B ~ Binomial(n, 1/2),
// whatever the times' distribution. k is the largest rank whose coverage is at least `confidence`; below 6 repeats
// no rank reaches 95% and the interval is [min, max] with its own, lower, coverage (`level`, written in the row).
//
// A ratio's interval (speed_ratio) is a percentile bootstrap paired by frame: every frame's base and method times
// were measured on the same batch seed and frame, so frames are resampled together (with replacement), and each
// frame's repeats are resampled within it; each resample's ratio is (method rays / sum of method medians) over
// (base rays / sum of base medians). A fixed bootstrap seed makes the interval reproducible from the committed
// rows. docs/statistics.md states the method and its limits.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace raycoh {

// The default confidence of every interval raycoh prints or writes.
constexpr double kSpeedConfidence = 0.95;

struct MedianInterval {
  double median = 0, lo = 0, hi = 0;
  double level = 0;  // the interval's coverage (0: one sample, no interval)
};

// The median of `samples` and its order-statistic interval (above). Empty samples: all 0.
MedianInterval median_interval(std::vector<double> samples, double confidence = kSpeedConfidence);

// One frame's repeated times of one method (any unit, all frames the same) and the rays each repeat traced.
struct FrameTimes {
  std::vector<double> times;
  double rays = 0;
};

struct SpeedRatio {
  double ratio = 0;  // method speed / base speed, from the medians (> 1: the method is faster)
  double lo = 0, hi = 0;
  bool has_interval = false;  // false when no frame has two repeats on either side: one number, no interval
};

// The speed ratio of `method` to `base` over the same frames (paired by index; both the same length) with its
// paired bootstrap interval (above). Frames where either side has no time are skipped.
SpeedRatio speed_ratio(const std::vector<FrameTimes>& base, const std::vector<FrameTimes>& method,
                       double confidence = kSpeedConfidence);

// One method's times by frame (frame index -> that frame's repeats and rays), as the table and the report hold them.
using FrameSeries = std::map<int, FrameTimes>;

// speed_ratio over the frames both series hold.
SpeedRatio paired_ratio(const FrameSeries& base, const FrameSeries& method);

// A series' speed from its medians: rays / sum of the frames' median times (rays per time unit).
double series_speed(const FrameSeries& s);

// The top of a measured ranking, as a table line may state it: the method with the highest series_speed is
// "<label> fastest, <ratio to base>" only when its paired interval over every other method excludes 1; otherwise
// "indistinguishable at the top: <label> <ratio>, <label> <ratio>..." lists every method the interval cannot tell
// from it; without repeats, "<label> highest, <ratio> (no repeated times in the rows: no interval, not called
// fastest)". Ratios are to `base` (noopt) with their intervals.
std::string top_of_ranking(const std::vector<std::pair<std::string, const FrameSeries*>>& methods,
                           const FrameSeries& base);

// What a ratio's interval allows a reader to say: "faster" (the interval lies above 1), "slower" (below 1),
// "indistinguishable" (it holds 1) or "no interval" (one repeat: a model's or simulator's deterministic figure, or
// --repeat 1).
std::string speed_verdict(const SpeedRatio& r);

// "1.45x [1.41, 1.49]", or "1.45x" without an interval.
std::string ratio_text(const SpeedRatio& r);

}  // namespace raycoh
