// `raycoh converge`: error against time, equal-time error and equal-error time (methods in converge.cpp's doc
// block, schema in results/README.md).
#pragma once

#include <string>
#include <vector>

#include "core/params.h"
#include "harness/image/render_options.h"
#include "records/provenance.h"
#include "records/shard.h"
#include "shading/denoise.h"

namespace raycoh {

// `raycoh converge --scene S --generators noopt,ours --time 60s`
struct ConvergeOptions {
  RenderCommon common;
  std::string scene = "cornell";
  std::vector<PluginSpec> generators{{"noopt", ""}, {"ours", ""}};  // the first is the baseline of the ratios
  double time_s = 10;        // --time (0, 1e6] seconds of rendering (frame wall time) per generator
  int max_frames = 1 << 20;  // --max-frames [1, 1 << 20]: stop a generator earlier
  int ref_frames = 512;
  bool ref_frames_known = true;  // false: --reference is a file without its cache sidecar (ref_frames written empty)
  std::string cache_dir;
  std::string reference;
  std::string out = "raycoh-converge.csv";  // per-frame rows; ratios go to <out stem>-summary.csv
  // --shard I/N: only this shard's generators (units scene x generator); each shard also renders the baseline
  // beside them for its ratios (its rows are written by the baseline's shard only). Join with raycoh merge.
  Shard shard;
  // The modeled GPU clock (harness/image/gpu_clock.h): a `simt` tracer spec, or "none" for no modeled time.
  std::string gpu_model = "simt";
  int model_every = 1;  // --model-every [1, kMaxFrames]: model frames 0, N, 2N, ...; the others hold the last
  Denoiser denoise = Denoiser::None;  // --denoise none|oidn: the error after denoising at frames 1, 2, 4, 8, ...
};
int run_converge(const ConvergeOptions& options, const Provenance& provenance);

}  // namespace raycoh
