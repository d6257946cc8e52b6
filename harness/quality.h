// The options and runners of the rendering and image-quality commands (docs/design.md section 5): `render`, `quality`
// (the paper's Table 2 layout), `converge` (error against time, equal-time error and equal-error time) and
// `compare`, each in its own .cpp with its CLI binding; shared checks and the reference in render_common.h. CSV
// schemas are in results/README.md; methods in quality.cpp's and converge.cpp's doc blocks.
//
// Defaults are written here once (the CLI shows them) and are small enough for a 2-core machine (160x120,
// 32 frames, 512-frame references). The runners validate every value before anything is rendered (the one
// validation layer); errors are raycoh::Error naming the option (e.g. "--frames 0: ...").
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/params.h"
#include "records/curves.h"
#include "records/provenance.h"
#include "records/quality_row.h"
#include "records/shard.h"
#include "shading/denoise.h"
#include "shading/image.h"
#include "shading/metrics.h"

namespace raycoh {

// Settings every rendering command shares.
struct RenderCommon {
  PluginSpec tracer{"cpu", ""};
  int width = 160, height = 120;  // --res, each in [1, 16384] ([11, 16384] where SSIM is computed)
  uint32_t seed = 1;              // --seed
  int max_depth = 5;              // --max-depth [1, 64]: scattering events per path
  int rr_depth = 3;               // --rr-depth [1, 64]: Russian roulette from this bounce on
  // --tone-map aces|clamp, --exposure auto|(0, 1e6]: PNG output, PSNR and SSIM. Auto exposure (the default) is
  // resolved on the reference image (quality, converge, compare) or on the rendered image (render).
  ToneMap tone_map{ToneMapKind::Aces, 1.f, true};
  // --metrics tonemapped|linear (quality, converge): the space of PSNR and SSIM (shading/metrics.h).
  MetricSpace metrics = MetricSpace::ToneMapped;
  std::string protocol = "ci";  // --protocol (quality, converge, reference): recorded in the CSV
  bool force = false;           // --force: replace an existing --out (and what its .partial holds)
};

// --protocol ci|paper of quality, converge and reference: one name for a set of settings, each of which an option
// given alongside replaces.
//   ci     the defaults above: 160x120, 32 frames, 512-frame reference, tone-mapped PSNR/SSIM (fits CI and a laptop)
//   paper  the paper's Table 2: 1920x1080, 128 frames, 4096-frame reference, linear radiance (no tone map)
// For converge, `frames` is --max-frames; for reference, `ref_frames` is --frames.
struct Protocol {
  std::string name;
  int width = 0, height = 0, frames = 0, ref_frames = 0;
  MetricSpace metrics = MetricSpace::ToneMapped;
};
// Throws raycoh::Error naming `option` and the choices.
Protocol protocol_named(const std::string& option, const std::string& name);
// Sets c.protocol, and c.width/height (--res), c.metrics (--metrics), *frames (frames_option) and *ref_frames
// (ref_option) from the protocol unless given(option) says the option was given; frames and ref_frames may be null.
void apply_protocol(const Protocol& p, const std::function<bool(const std::string&)>& given, RenderCommon& c,
                    int* frames, const char* frames_option, int* ref_frames, const char* ref_option);

// `raycoh render --scene S --generator G --frames N --out img.exr [--crop x,y,w,h]...`
struct RenderOptions {
  RenderCommon common;
  std::string scene = "cornell";
  PluginSpec generator{"noopt", ""};
  int frames = 32;                 // --frames [1, 1 << 20]
  std::string out = "render.exr";  // .exr (float), .png (tone-mapped 8-bit) or .pfm
  std::vector<Crop> crops;         // each written as <out stem>-crop<i><out extension>
  std::string device = "cpu";      // --device cpu | cuda (the device path tracer, cuda/device_path_tracer.h)
};
int run_render(const RenderOptions& options, const Provenance& provenance);

// `raycoh quality --scenes ... --generators noopt,ours --frames 128 --ref-frames 4096`
struct QualityOptions {
  RenderCommon common;
  std::vector<std::string> scenes{"cornell"};
  std::vector<PluginSpec> generators{{"noopt", ""}, {"ours", ""}};
  int frames = 32;        // --frames [1, 1 << 20]: frames per render
  int ref_frames = 512;   // --ref-frames [1, 1 << 20]: NoOpt frames of the reference
  int bias_renders = 4;   // --bias-renders [1, 256]: independent renders per generator (seeds seed .. seed+R-1)
  std::string cache_dir;  // --cache: reference cache folder ("" = $RAYCOH_CACHE or results/cache)
  std::string reference;  // --reference: use this .exr/.pfm as the reference (one scene only) instead of the cache
  std::string out = "raycoh-quality.csv";
  std::string image_dir;  // --images: where renders and crops go ("" = <out stem>-images)
  std::vector<Crop> crops;
  Shard shard;  // --shard I/N: only this shard's scene x generator units (records/shard.h); join with raycoh merge
  Denoiser denoise = Denoiser::None;  // --denoise none|oidn: every figure on the denoised renders too
  // For commands built on quality (`raycoh tune`), not options: called with every row of a scene in generator
  // order, measured or resumed; returning true leaves the scene's later generators unmeasured. The console tables
  // are printed only when `console` (they need every row).
  std::function<bool(const QualityRow&)> after_row;
  bool console = true;
};
int run_quality(const QualityOptions& options, const Provenance& provenance);

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
  // The modeled GPU clock (harness/gpu_clock.h): a `simt` tracer spec, or "none" for no modeled time.
  std::string gpu_model = "simt";
  int model_every = 1;  // --model-every [1, kMaxFrames]: model frames 0, N, 2N, ...; the others hold the last
  Denoiser denoise = Denoiser::None;  // --denoise none|oidn: the error after denoising at frames 1, 2, 4, 8, ...
};
int run_converge(const ConvergeOptions& options, const Provenance& provenance);

// `raycoh compare test.exr reference.exr`: prints every metric of shading/metrics.h.
struct CompareOptions {
  std::string test, reference;
  ToneMap tone_map{ToneMapKind::Aces, 1.f, true};
};
int run_compare(const CompareOptions& options);

// "60s", "1.5m", "500ms", "2h" or a plain number of seconds; throws raycoh::Error naming `what` unless finite
// and > 0.
double parse_duration(const std::string& what, const std::string& text);

}  // namespace raycoh
