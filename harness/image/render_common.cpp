#include "harness/image/render_common.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "core/error.h"
#include "harness/common/memory_check.h"
#include "harness/common/progress.h"
#include "harness/image/render_device.h"
#include "plugins/tracer_registry.h"
#include "shading/metrics.h"
#include "shading/reference.h"

namespace raycoh {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

std::string safe_name(const std::string& text) {
  std::string out;
  for (char c : text) out += std::isalnum(static_cast<unsigned char>(c)) || c == '-' ? c : '_';
  return out;
}

RenderSettings settings_of(const RenderCommon& c, uint32_t seed) {
  RenderSettings s;
  s.width = c.width;
  s.height = c.height;
  s.seed = seed;
  s.max_depth = c.max_depth;
  s.rr_depth = c.rr_depth;
  return s;
}

void check_frames(const char* option, int frames) {
  if (frames < 1 || frames > kMaxFrames)
    throw Error(fmt::format("{} {}: must be in [1, {}]", option, frames, kMaxFrames));
}

void check_exposure(const ToneMap& tm) {
  if (!tm.auto_exposure && (!(tm.exposure > 0.f) || !(tm.exposure <= 1e6f)))
    throw Error(fmt::format("--exposure {}: must be in (0, 1e6] (or auto)", tm.exposure));
}

void check_common(const RenderCommon& c, bool needs_ssim) {
  if (c.width < 1 || c.width > 16384 || c.height < 1 || c.height > 16384)
    throw Error(fmt::format("--res {}x{}: width and height must be in [1, 16384]", c.width, c.height));
  if (needs_ssim && (c.width < kSsimWindow || c.height < kSsimWindow))
    throw Error(fmt::format("--res {}x{}: image-quality runs need at least {}x{} pixels (the SSIM window)", c.width,
                            c.height, kSsimWindow, kSsimWindow));
  if (c.max_depth < 1 || c.max_depth > 64) throw Error(fmt::format("--max-depth {}: must be in [1, 64]", c.max_depth));
  if (c.rr_depth < 1 || c.rr_depth > 64) throw Error(fmt::format("--rr-depth {}: must be in [1, 64]", c.rr_depth));
  check_exposure(c.tone_map);
  check_device(c.device);
  check_memory(fmt::format("--res {}x{}", c.width, c.height), rendering_bytes(c.width, c.height));
  std::vector<std::string> names;
  for (const TracerInfo& t : tracer_infos()) names.push_back(t.name);
  if (std::find(names.begin(), names.end(), c.tracer.name) == names.end())
    throw Error(fmt::format("--tracer {}: unknown tracer; valid tracers: {}", c.tracer.text(), join(names)));
}

void check_crops(const std::vector<Crop>& crops, int width, int height) {
  for (const Crop& c : crops) check_crop("--crop", c, width, height);
}

std::vector<std::unique_ptr<Generator>> make_generators(const std::string& option,
                                                        const std::vector<PluginSpec>& specs) {
  if (specs.empty()) throw Error(option + ": empty list");
  std::vector<std::unique_ptr<Generator>> out;
  std::vector<std::string> labels;
  for (const PluginSpec& s : specs) {
    if (std::find(labels.begin(), labels.end(), s.text()) != labels.end())
      throw Error(fmt::format("{}: '{}' is listed twice", option, s.text()));
    labels.push_back(s.text());
    out.push_back(make_generator(s));
  }
  return out;
}

std::unique_ptr<LoadedScene> load(const std::string& spec, const PluginSpec& tracer) {
  const auto t0 = Clock::now();
  auto ls = std::make_unique<LoadedScene>(spec, tracer);
  std::string lights = fmt::format("{} emissive triangles", ls->scene.emissive_tris.size());
  if (!ls->scene.lights.empty()) lights += fmt::format(" + {} punctual lights", ls->scene.lights.size());
  if (ls->scene.env.enabled) lights += " + sky and sun";
  std::fprintf(stderr, "%s: %zu triangles, %s; loaded and BVH built in %.2f s\n", ls->scene.name.c_str(),
               ls->scene.triangle_count(), lights.c_str(), seconds_since(t0));
  return ls;
}

Image read_image_for(const std::string& option, const std::string& path) {
  try {
    return read_image(path);
  } catch (const Error& e) {
    throw Error(fmt::format("{}: {}", option, e.what()));
  }
}

ReferenceImage obtain_reference(const LoadedScene& ls, const std::string& spec, const RenderCommon& c, int ref_frames,
                                const std::string& cache_dir, const std::string& explicit_path) {
  ReferenceImage out;
  if (!explicit_path.empty()) {
    out.image = read_image_for("--reference", explicit_path);
    if (out.image.width != c.width || out.image.height != c.height)
      throw Error(fmt::format("--reference {}: the image is {}x{} but the renders are {}x{} (--res)", explicit_path,
                              out.image.width, out.image.height, c.width, c.height));
    out.path = explicit_path;
    out.kind = "file";
    const std::string half = half_reference_path(explicit_path);
    if (fs::is_regular_file(half)) {
      out.first_half = read_image_for("--reference (half)", half);
      if (out.first_half.width != c.width || out.first_half.height != c.height)
        throw Error(fmt::format("--reference {}: its half image {} is {}x{}, the reference {}x{}", explicit_path, half,
                                out.first_half.width, out.first_half.height, c.width, c.height));
    }
    return out;
  }
  ReferenceRequest req = reference_request(spec, c, ref_frames, cache_dir);
  const auto time = std::make_shared<DeviceTime>();
  if (c.device != "cpu") render_reference_on_device(req, ls, time);
  Progress bar;
  const std::string label = fmt::format("{} reference", ls.scene.name);
  req.progress = [&](int done, int total) { bar.update(0, 1, done - 1, total, label); };
  const Reference ref = get_reference(ls.scene, ls.bvh, req);
  bar.clear();
  if (ref.from_cache)
    std::fprintf(stderr, "    reference: %s (cached, %d frames)\n", ref.path.c_str(), ref_frames);
  else
    std::fprintf(stderr, "    reference: rendered %d frames in %.1f s%s -> %s\n", ref_frames, ref.render_s,
                 device_time_text(*time).c_str(), ref.path.c_str());
  if (ref.non_finite > 0)
    std::fprintf(stderr, "    reference: %llu NaN/Inf frame samples were left out (counted, not added)\n",
                 static_cast<unsigned long long>(ref.non_finite));
  out.image = ref.image;
  out.path = ref.path;
  out.kind = ref.from_cache ? "cache" : "rendered";
  out.non_finite = ref.non_finite;
  out.first_half = ref.first_half;
  return out;
}

ReferenceRequest reference_request(const std::string& spec, const RenderCommon& c, int ref_frames,
                                   const std::string& cache_dir) {
  ReferenceRequest req;
  req.scene_spec = spec;
  req.settings = settings_of(c, c.seed + kReferenceSeedOffset);
  req.frames = ref_frames;
  req.tracer = c.device == "cpu" ? c.tracer : PluginSpec{"cuda", "bvh=bvh2"};
  req.device = c.device;
  req.cache_dir = cache_dir;
  return req;
}

std::string device_time_text(const DeviceTime& t) {
  if (t.frames == 0) return "";
  return fmt::format("; GPU time {:.3f} ms per frame ({}, on {}: CUDA events around each frame)", t.ms / t.frames,
                     t.clock, t.device);
}

Protocol protocol_named(const std::string& option, const std::string& name) {
  if (name == "ci") return {"ci", 160, 120, 32, 512, MetricSpace::ToneMapped};
  if (name == "paper") return {"paper", 1920, 1080, 128, 4096, MetricSpace::Linear};
  throw Error(
      fmt::format("{} '{}': expected ci (160x120, 32 vs 512 frames, tone-mapped) or paper (1920x1080, 128 "
                  "vs 4096 frames, linear)",
                  option, name));
}

void apply_protocol(const Protocol& p, const std::function<bool(const std::string&)>& given, RenderCommon& c,
                    int* frames, const char* frames_option, int* ref_frames, const char* ref_option) {
  c.protocol = p.name;
  if (!given("--res")) {
    c.width = p.width;
    c.height = p.height;
  }
  if (!given("--metrics")) c.metrics = p.metrics;
  if (frames && !given(frames_option)) *frames = p.frames;
  if (ref_frames && !given(ref_option)) *ref_frames = p.ref_frames;
}

std::string stem_path(const std::string& path) {
  const fs::path p(path);
  return (p.parent_path() / p.stem()).string();
}

std::string display_extension() { return image_io_available() ? ".png" : ".pfm"; }

std::optional<ReferenceNoise> noise_of_reference(const ReferenceImage& ref, const ToneMap& tm, MetricSpace space) {
  if (ref.first_half.empty()) {
    std::fprintf(stderr, "    reference noise: unknown (no half-reference: %s)\n",
                 ref.kind == "file" ? "no <stem>-half1 image beside --reference"
                                    : "the reference frames are not two equal halves of whole 64-frame blocks");
    return std::nullopt;
  }
  const ReferenceNoise noise = reference_noise(ref.image, ref.first_half, tm, space);
  std::fprintf(stderr, "    reference noise: MSE %.3g, relMSE %.3g (from its two half-references)\n", noise.mse,
               noise.rel_mse);
  return noise;
}

void warn_reference_noise(const std::string& what, double share) {
  if (share > kNoiseWarnShare)
    std::fprintf(stderr,
                 "    warning: %s: the reference's own noise is %.0f%% of an error figure (ref_noise_share); "
                 "render a longer reference (--ref-frames)\n",
                 what.c_str(), 100 * share);
}

}  // namespace raycoh
