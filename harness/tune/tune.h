// `raycoh tune --scene S`: the fastest setting of `ours` (or `contiguous`) whose image error stays within a budget
// of NoOpt's, on one scene. Three stages, each resumable (an interrupted tune run again measures only what is
// missing):
//   speed    every setting of --space and noopt, traced by --tracer (simt: the timing model's MODELED MRay/s; cpu,
//            embree, cuda: measured), --speed-frames frames: <out stem>-speed.csv (the experiment CSV of table and
//            sweep, results/README.md);
//   error    noopt and every setting's image (settings differing only in `order` share one), --seeds renders of
//            --frames frames each (seeds seed .. seed + seeds - 1) against a --ref-frames NoOpt reference from the
//            cache, rendered by --render-tracer: <out stem>-quality.csv (quality's CSV, with its per-render
//            columns). --search fastest (the default) measures the images in order of their fastest setting and
//            stops at the first that meets the budget: the recommendation is the grid's, since a setting's verdict
//            does not depend on the others; settings slower than it keep no error figures (the front is the
//            measured settings'). --search grid measures every image.
//   decision harness/tune/tune_select.h: per setting the error ratios to NoOpt with their 95% interval over the seeds,
//            the verdict against --budget, the Pareto front of speed against the error axis, the recommendation
//            (or the closest miss and why) and the paper's default (8x8, K = 8, tile order, paper rule, Duff frame)
//            for comparison: <out> (records/tune_row.h), and the console. The speed call: a setting is recommended
//            over the paper's default only when measured faster at 95% (harness/tune/tune_select.h settle_speed); each
//            row says how many waves of the GPU (model) its batch fills, and the console warns below two.
//   confirm  --confirm N: the speed call re-measured on N fresh seeds (harness/tune/tune_confirm.h).
#pragma once

#include <string>

#include "core/params.h"
#include "harness/tune/tune_space.h"
#include "records/provenance.h"
#include "records/shard.h"

namespace raycoh {

// The speed stage and the speed call: what is timed, how the settings are ranked, and the call's re-measurement.
struct TuneSpeedOptions {
  PluginSpec tracer{"simt", ""};  // --tracer
  int frames = 2;                 // --speed-frames [1, 1000]
  int repeats = 0;                // --repeat [0, 1000]: timed traces per batch (0: the tracer's default)
  std::string rank = "e2e";       // --rank e2e | trace
  // --speed-csv: take the speed stage from this table/sweep CSV (one scene, one tracer; e.g. <stem>-speed.csv of a
  // tune run on a GPU machine) instead of measuring it here; it must hold noopt and every setting at --res.
  std::string csv;
  // --confirm N [1, 64] (0: off): after the decision, re-measure the speed call on N fresh seeds
  // (harness/tune/tune_confirm.h).
  int confirm = 0;
};

// The error stage: the renders of every image against the NoOpt reference, and the budget they are judged by.
struct TuneErrorOptions {
  PluginSpec tracer{"cpu", ""};     // --render-tracer: the quality renders' (cpu | embree)
  std::string device = "cpu";       // --render-device cpu|cuda: their path tracer (harness/image/render_options.h)
  int frames = 16;                  // --frames [1, 1 << 20]: frames per render
  int seeds = 4;                    // --seeds [2, 256]: renders per setting (the spread needs two)
  int ref_frames = 512;             // --ref-frames [1, 1 << 20]
  int max_depth = 5, rr_depth = 3;  // --max-depth, --rr-depth [1, 64]
  std::string budget = "ds8=1.05,flip=1.05,bias=none";  // --budget
  // --quality-csv: the error stage's file (default <out stem>-quality.csv). The error does not depend on the speed
  // tracer, so tunes of one scene ranked by different speeds can share it: each measures only the images missing.
  std::string csv;
  std::string cache_dir, image_dir;  // --cache, --images: "" = $RAYCOH_CACHE or results/cache; <out stem>-images
};

struct TuneOptions {
  std::string scene;
  std::string generator = "ours";  // ours | contiguous
  int width = 480, height = 270;   // --res, each in [11, 16384]
  uint32_t seed = 1;               // --seed: of both stages
  std::string space = "tile=8x8,16x8,16x16,32x8 k=8,16,32,64 order=tile,group hybrid=paper,donor frame=duff,rotate";
  std::string search = "fastest";  // fastest | grid
  TuneSpeedOptions speed;
  TuneErrorOptions error;
  std::string out = "raycoh-tune.csv";
  bool force = false;
  Shard shard;  // --shard I/N (with --search grid): this shard's units of both stages
};
int run_tune(const TuneOptions& options, const Provenance& provenance);

}  // namespace raycoh
