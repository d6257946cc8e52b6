// The record of one `raycoh tune` row (one setting of the search space on one scene) and its CSV column table
// (results/README.md). The row joins the setting's speed (from <out stem>-speed.csv, a sweep-layout experiment
// CSV) and its error ratios to NoOpt (from <out stem>-quality.csv, a quality CSV) with the decision of
// harness/tune/tune_select.h.
#pragma once

#include <cstdint>
#include <string>

#include "records/provenance.h"
#include "records/schema.h"

namespace raycoh {

struct TuneRow {
  std::string scene_spec, scene;
  std::string setting;  // the generator spec ("ours:tile=16x8,k=32,order=group,hybrid=donor,frame=rotate")
  std::string generator;
  int tile_w = 0, tile_h = 0, k = 0;
  std::string order, hybrid, frame;
  std::string tracer_spec;                  // the speed tracer, as tables name it
  std::string speed_csv;                    // where the speeds come from: this run's <stem>-speed.csv or --speed-csv
  std::string speed_kind;                   // modeled (a timing model's figure) | measured
  std::string rank;                         // e2e | trace: which speed ranks the settings
  double mray_s = 0, speedup = 0;           // the ranked speed and its ratio to noopt's
  double trace_mray_s = 0, e2e_mray_s = 0;  // both speeds (MRay/s)
  double noopt_mray_s = 0;                  // noopt's ranked speed
  // The speedup's paired interval over frames and repeats (records/speed_interval.h; NaN: one run, no interval),
  // the ranked speed's ratio to the paper's default with its interval, and what that interval allows:
  // faster | slower | indistinguishable | no interval.
  double speedup_lo = 0, speedup_hi = 0;
  double vs_paper = 0, vs_paper_lo = 0, vs_paper_hi = 0;
  std::string vs_paper_verdict;
  int speed_repeats = 0;      // timed repeats per frame of the speed stage (1: a model's run, or --repeat 1)
  double waves = 0;           // the batch's rays / the rays the GPU holds resident (NaN: not a GPU, or unknown)
  std::string render_tracer;  // the tracer of the quality renders
  std::string render_device;  // cpu | cuda: the path tracer the quality renders ran on (--render-device)
  int width = 0, height = 0, frames = 0, ref_frames = 0, seeds = 0;
  uint32_t seed = 0;
  bool error_measured = false;
  double ds8 = 0, ds8_lo = 0, ds8_hi = 0;  // error ratios to noopt (mean, 95% interval; NaN: not measured)
  double rel = 0, rel_lo = 0, rel_hi = 0;
  double flip = 0, flip_lo = 0, flip_hi = 0;
  std::string bias_verdict;  // consistent | biased | "" (not measured)
  std::string budget;        // "ds8=1.05,flip=1.05,bias=none"
  bool meets_budget = false, front = false, recommended = false, closest_miss = false, paper_default = false;
  bool fastest_passing = false;  // the fastest setting within the budget (recommended unless the speed call chose
                                 // the paper's default: harness/tune/tune_select.h settle_speed)
  std::string reason;            // why it misses the budget ("" when it meets it)
  std::string search;            // grid | fastest
  Provenance provenance;
};

const Schema<TuneRow>& tune_schema();

// One line of `raycoh tune --confirm N` (<out stem>-confirm.csv, harness/tune/tune_confirm.h): the search's speed call
// of `setting` against `baseline` (the paper's default, or noopt when the recommendation is the paper's default)
// re-measured at one fresh seed (kind "seed"), or over every fresh seed's frames together (kind "pooled").
struct TuneConfirmRow {
  std::string scene_spec, scene;
  std::string kind;   // seed | pooled
  std::string seeds;  // the seed, or the seeds pooled ("5;6")
  std::string setting, baseline;
  std::string claim;                 // the search's call: faster | slower | indistinguishable (of setting vs baseline)
  double search_ratio = 0;           // the search's ratio
  double ratio = 0, lo = 0, hi = 0;  // this seed's ratio (setting / baseline speed) and its 95% interval (NaN: none)
  std::string verdict;               // faster | slower | indistinguishable | no interval (this seed's)
  std::string held;                  // held | not held | indistinguishable
  double setting_speedup = 0, setting_speedup_lo = 0, setting_speedup_hi = 0;  // the setting's speed over noopt's
  double setting_mray_s = 0, baseline_mray_s = 0, noopt_mray_s = 0;
  std::string tracer_spec, speed_kind, rank, speed_csv;
  int width = 0, height = 0, speed_frames = 0, repeats = 0;
  double waves = 0;
  Provenance provenance;
};

const Schema<TuneConfirmRow>& tune_confirm_schema();

}  // namespace raycoh
