// `raycoh stability`: how far a scene's rays can be trusted. For each scene, the primary batch and the secondary
// batch of every generator are traced with the float tracer (`cpu`, our traversal) and checked against the
// double-precision reference (tracers/double_reference.h) and against their own shading points; every check
// is a case with a measured rate and, where the rate gates a run, a threshold (docs/stability.md lists them).
// Exit code 3 when any rate exceeds its threshold (so it can gate a benchmark run), 2 for bad input.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/params.h"
#include "records/provenance.h"

namespace raycoh {

struct StabilityOptions {
  std::vector<std::string> scenes;
  std::vector<PluginSpec> generators{{"noopt", ""}, {"ours", ""}, {"direct", ""}};
  std::vector<PluginSpec> encoders{{"origin", ""}, {"twopoint", ""}};  // key degeneracy; `none` makes no keys
  int width = 160, height = 120;                                       // --res, each in [1, 16384]
  uint32_t seed = 1;
  int frame = 0;        // --frame [0, 2^30]
  size_t max_rays = 0;  // rays per batch checked against the double reference (evenly spaced); 0 = all
  // --threshold CASE=RATE: replaces a case's threshold (or gives a reported one a threshold); CASE is a case name
  // ("self_intersection", "key_degeneracy:origin") or the part before its ':' ("key_degeneracy").
  std::vector<std::pair<std::string, double>> thresholds;
  std::string out;     // optional CSV, one row per scene x batch x case
  bool force = false;  // replace an existing --out
};

// One measured case: `count` of `of` (rays, or pairs for reuse), and the threshold its rate is held to
// (negative: reported only, never gates).
struct StabilityCase {
  std::string batch;  // "primary", or the generator's spec
  std::string name;   // e.g. "self_intersection", "key_degeneracy:origin"
  size_t count = 0, of = 0;
  double threshold = -1.0;
  double rate() const { return of > 0 ? static_cast<double>(count) / static_cast<double>(of) : 0.0; }
  bool gated() const { return threshold >= 0.0; }
  bool failed() const { return gated() && rate() > threshold; }
};

struct StabilityReport {
  std::string scene, spec;
  size_t triangles = 0;
  std::vector<StabilityCase> cases;
  bool failed() const;
  const StabilityCase* find(const std::string& batch, const std::string& name) const;
};

// Thresholds of the gated cases (the goals).
constexpr double kSelfIntersectionThreshold = 1e-5;
constexpr double kWrongHitThreshold = 1e-6;
constexpr double kDisplacedThreshold = 1e-5;  // origins offset by more than 1e-3 of the scene's diagonal

// Every case name a report holds (encoder cases as "key_degeneracy"), for checking --threshold.
const std::vector<std::string>& stability_case_names();

// Measures one scene (throws raycoh::Error for bad input).
StabilityReport measure_stability(const std::string& scene_spec, const StabilityOptions& options);

int run_stability(const StabilityOptions& options, const Provenance& provenance);

}  // namespace raycoh
