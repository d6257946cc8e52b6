// The measurement stages of `raycoh tune` (harness/tune/tune.h): speed of every setting, then the error of their
// images, as candidates for harness/tune/tune_select.h.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "harness/tune/tune.h"
#include "harness/tune/tune_select.h"
#include "records/quality_row.h"

namespace raycoh {

struct TuneMeasured {
  std::string scene;                       // the scene's name
  std::string tracer_label;                // the speed tracer as tables name it
  std::string speed_source;                // the --speed-csv file, or the <stem>-speed.csv this run measured
  bool modeled = false;                    // the speeds are a timing model's
  double noopt_speed = 0;                  // noopt's ranked speed
  int repeats = 0;                         // timed repeats per frame of the speed stage (1: no interval)
  double wave_rays = 0;                    // rays one wave of the GPU holds (0: not a GPU, or unknown)
  std::string wave_basis;                  // whose figure wave_rays is
  std::vector<TuneCandidate> candidates;   // one per setting, in the order of `expand`
  std::map<std::string, QualityRow> rows;  // quality rows by image spec ("noopt" too)
};

// <out stem>-speed.csv and <out stem>-quality.csv.
std::string tune_speed_path(const TuneOptions& o);
std::string tune_quality_path(const TuneOptions& o);

// The error stage's methods of a grid search in the order its shards deal them (noopt, the paper's default image,
// then every image of the space once): what `raycoh merge` needs to join a sharded tune's quality files.
std::vector<std::string> tune_quality_methods(const std::string& space, const std::string& generator);

// Runs (or resumes) both stages; std::nullopt for a shard that is not the whole run (its files are written).
std::optional<TuneMeasured> measure_tune(const TuneOptions& o, const TuneBudget& budget,
                                         const std::vector<TuneSetting>& settings, const Provenance& provenance);

}  // namespace raycoh
