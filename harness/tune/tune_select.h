// `raycoh tune`'s decision, apart from any measurement (so that tests give it known answers):
//
// Error ratios: for each budget metric, the renders of a setting and of NoOpt with the same seed are paired,
// r_i = x_i / x_noopt,i, and the ratio is their geometric mean with a two-sided 95% Student-t interval over the
// seeds, both on log r_i (seeds are independent; pairing takes out the share of the error both generators draw from
// the same random numbers; logs keep one seed's firefly in either render from swinging the mean, and the interval
// positive). A setting meets the budget when, for every metric of the budget, the interval's upper end is at most the
// bound (so it meets it at the seeds' confidence, not by luck of the seeds), and, with bias=none, the bias test
// does not reject it: neither the whole image's mean bias (verdict "biased") nor the share of pixels whose band
// excludes zero, when that share exceeds NoOpt's by more than z = 3.09 (one-sided 0.1%) standard errors of the
// difference of two proportions, the setting's in units its groups' correlation allows (the paper rule's bias sits on
// the hybrid groups' diffuse members: a part of the image the whole-image mean can average away).
//
// The recommendation: the fastest setting that meets the budget (speed: the ranked figure, end to end or trace).
// Without one, the closest miss: the setting whose worst upper end / bound is smallest among those the bias test
// accepts (among all when it accepts none), with the reason. The front: the settings no other measured setting beats
// in both speed and the error axis (ds8 when the budget has it, else rel, else flip; mean ratio).
//
// The speed call (settle_speed): the fastest setting within the budget is recommended over the paper's default only
// when its speed ratio to the paper's default has a paired interval over frames and repeats that excludes 1
// (records/speed_interval.h, 95%). When the interval holds 1 (or lies below it) and the paper's default meets the
// budget too, the two are indistinguishable at this confidence and the paper's default is recommended. A modelling
// tracer's speeds (simt: one deterministic run) have no interval; its ranking stands as the model's point figures.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "harness/tune/tune_space.h"
#include "records/speed_interval.h"

namespace raycoh {

struct RatioStat {
  double mean = std::nan(""), lo = std::nan(""), hi = std::nan("");
  int n = 0;  // pairs with both values finite
};
// Pairs x[i] with base[i]; pairs where either is not finite and positive are left out. Fewer than 2 pairs: the
// mean alone (lo = hi = mean when n = 1, all NaN when n = 0).
RatioStat paired_ratio(const std::vector<double>& x, const std::vector<double>& base);

struct TuneCandidate {
  TuneSetting setting;
  double speed = 0, trace_speed = 0;  // MRay/s: the ranked figure (end to end or trace) and the trace's
  bool error_measured = false;        // false: left out by --search fastest (a faster setting met the budget)
  RatioStat ds8, rel, flip;
  std::string bias_verdict;  // "consistent" | "biased" | "" (not measured)
  // The per-pixel bias test's share of pixels whose 95% band excludes zero, the setting's and NoOpt's (which is not
  // 5%: reference noise, skewed samples; harness/image/quality.cpp), and the independent units of each share: NoOpt's
  // pixels, the setting's pixels / (1 + (K - 1) rho), rho = K / (tile pixels) for ours (the chance that two pixels
  // of a tile share a group in a frame), 1 for contiguous (fixed groups).
  double bias_share = std::nan(""), noopt_bias_share = std::nan(""), share_units = 0, noopt_units = 0;
  // The ranked speed's ratio to noopt's and to the paper's default with their paired intervals (has_interval false:
  // one run, a model's figure, or not measured).
  SpeedRatio to_noopt, to_paper;
  double waves = std::nan("");  // the batch's rays over the rays the GPU holds resident (NaN: not a GPU, unknown)
};

struct TuneVerdict {
  bool pass = false;
  double excess = INFINITY;  // worst upper end / bound over the budget's metrics (<= 1 when they pass)
  bool bias_rejected = false;
  std::string reason;  // "" when pass; else e.g. "ds8 1.12 [1.08, 1.16] > 1.05; bias test rejects"
};
TuneVerdict judge(const TuneCandidate& c, const TuneBudget& budget);

// The budget with its `paper` bounds replaced by the paper's default's upper ends (`paper`: its candidate; null or
// unmeasured: those bounds stay unresolvable and every setting misses them, "paper's default not measured").
TuneBudget resolve_paper(const TuneBudget& budget, const TuneCandidate* paper);

struct TuneChoice {
  std::vector<TuneVerdict> verdicts;  // per candidate
  std::vector<bool> front;            // per candidate
  int recommended = -1;               // index of the fastest passing candidate, -1 when none passes
  int closest_miss = -1;              // when none passes: the nearest miss (-1 when nothing was measured)
  std::string error_axis;             // "ds8", "rel" or "flip"
  // settle_speed: the fastest passing candidate (the recommendation before the speed call) and the call of its
  // speed against the paper's default: speed_verdict's words, or "" when it is the paper's default or none passes.
  int fastest_passing = -1;
  std::string speed_call;
};
// `budget` resolved already (resolve_paper).
TuneChoice choose(const std::vector<TuneCandidate>& candidates, const TuneBudget& budget);

// The speed call above: recommended becomes the paper's default (index `paper`, -1: not among the candidates) when
// the fastest passing candidate is not measured faster than it and it meets the budget.
void settle_speed(TuneChoice& choice, const std::vector<TuneCandidate>& candidates, int paper);

// z of the setting's excluded share over NoOpt's (NaN without both).
double bias_share_z(const TuneCandidate& c);

// The error axis's mean ratio of a candidate (the front's and the plot's y).
double axis_value(const TuneCandidate& c, const std::string& axis);

}  // namespace raycoh
