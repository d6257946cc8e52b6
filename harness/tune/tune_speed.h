// The speed stage of `raycoh tune` (harness/tune/tune.h): noopt and every setting traced by the speed tracer (or read
// from --speed-csv), then read back from the experiment CSV into per-frame times, so that a setting's ratio to noopt
// and to the paper's default carries the paired interval of records/speed_interval.h (every repeat of every frame;
// a modelling tracer's one run: no interval), and each row says how many waves of the GPU its batch fills.
// `--confirm` measures its fresh seeds with the same code (harness/tune/tune_confirm.h).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/params.h"
#include "harness/tune/tune.h"
#include "records/speed_interval.h"

namespace raycoh {

// One method's speed: the ranked figure (end to end or trace) and the trace's, in MRay/s, and the ranked figure's
// times by frame (ms; every repeat of measured rows, the modeled time of a model's).
struct TuneSpeed {
  double ranked = 0, trace = 0;
  double rays_per_frame = 0;
  std::map<int, FrameTimes> times;
};

struct TuneSpeeds {
  std::string scene, tracer_label, source;  // source: the experiment CSV read
  bool modeled = false;
  int repeats = 0;                             // timed repeats per frame (1: a model's, or --repeat 1)
  std::map<std::string, TuneSpeed> by_method;  // "noopt" and each setting's spec
  // Rays one wave of the GPU holds (its SMs x the rays each keeps resident): 0 when the tracer is not a GPU or a
  // GPU model, or when it is unknown (a `cuda` CSV measured elsewhere, or no GPU here). wave_basis says whose.
  double wave_rays = 0;
  std::string wave_basis;
};

// Measures noopt and `methods` (generator specs) with the speed tracer at `seed` into `out` (resuming it), then
// reads it back; a shard that is not the whole run returns no methods.
TuneSpeeds measure_tune_speeds(const TuneOptions& o, const std::vector<std::string>& methods, uint32_t seed,
                               const std::string& out, const Provenance& provenance);

// Reads a table/sweep CSV of one scene and one tracer at --res (a tune's <stem>-speed.csv, or --speed-csv);
// `methods` must all be there (throws raycoh::Error naming `option` and the file otherwise).
TuneSpeeds read_tune_speeds(const TuneOptions& o, const std::string& path, const std::vector<std::string>& methods,
                            const std::string& option);

// The speed of `method` over `base` (> 1: faster) with its paired interval over the frames both hold.
SpeedRatio tune_speed_ratio(const TuneSpeed& base, const TuneSpeed& method);

// Rays one wave of `tracer`'s GPU holds (0: none or unknown): the simt model's SMs x resident warps x lanes; a `cuda`
// GPU's SMs x its resident thread limit, only when measured here (measured_here) and a GPU is present (basis then
// names it; else basis is left empty).
double gpu_wave_rays(const std::string& tracer, const std::string& params, bool measured_here, std::string& basis);

}  // namespace raycoh
