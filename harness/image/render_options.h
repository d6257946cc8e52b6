// The options every rendering command (`render`, `reference`, `quality`, `converge`, `tune`'s error stage) shares,
// and the --protocol presets; each command's own options are in its header (render.h, quality.h, converge.h,
// compare.h), the CLI bindings in render_cli.h, the shared checks and the reference in render_common.h. CSV schemas
// are in results/README.md.
//
// Defaults are written here once (the CLI shows them) and are small enough for a 2-core machine (160x120,
// 32 frames, 512-frame references). The runners validate every value before anything is rendered (the one
// validation layer); errors are raycoh::Error naming the option (e.g. "--frames 0: ...").
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "core/params.h"
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
  // --device cpu|cuda|cuda:pipeline=fused: the path tracer every frame is rendered on, the CPU's
  // (shading/path_tracer.h) or the device's (cuda/device_path_tracer.h, harness/image/render_device.h: its first
  // bounce materialized or fused); checked by check_device.
  std::string device = "cpu";
  bool force = false;  // --force: replace an existing --out (and what its .partial holds)
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

}  // namespace raycoh
