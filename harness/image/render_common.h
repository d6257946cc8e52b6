// What the rendering commands (`render`, `quality`, `converge`, `compare`) share: the checks of their common
// options (the one validation layer), a loaded scene with its tracer, the NoOpt reference, file names.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "generators/generator.h"
#include "harness/image/render_options.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "shading/metrics.h"
#include "shading/path_tracer.h"
#include "shading/reference.h"
#include "tracers/tracer.h"

namespace raycoh {

struct DeviceTime;

// The reference renders with seeds far from the test renders' seed .. seed + 255, so they are independent.
constexpr uint32_t kReferenceSeedOffset = 1000;
constexpr int kMaxFrames = 1 << 20;

// File-name-safe text: letters, digits and '-' kept, everything else '_'.
std::string safe_name(const std::string& text);
RenderSettings settings_of(const RenderCommon& c, uint32_t seed);

// Each throws raycoh::Error naming the option.
void check_frames(const char* option, int frames);  // [1, kMaxFrames]
void check_exposure(const ToneMap& tm);             // (0, 1e6] or auto
// check_common also checks --device (render_device.h check_device: cpu, or cuda with a device in a CUDA build).
void check_common(const RenderCommon& c, bool needs_ssim);
void check_crops(const std::vector<Crop>& crops, int width, int height);

// Generators made up front, so that a bad name or parameter fails before anything is rendered.
std::vector<std::unique_ptr<Generator>> make_generators(const std::string& option,
                                                        const std::vector<PluginSpec>& specs);

// A scene with its BVH and tracer, which keeps references to both (so it never moves).
struct LoadedScene {
  Scene scene;
  Bvh bvh;
  std::unique_ptr<Tracer> tracer;
  LoadedScene(const std::string& spec, const PluginSpec& tracer_spec)
      : scene(load_scene(spec)), bvh(build_bvh(scene)), tracer(make_tracer(tracer_spec, scene, bvh)) {}
  LoadedScene(const LoadedScene&) = delete;
  LoadedScene& operator=(const LoadedScene&) = delete;
};
// Loads and reports (stderr) the scene.
std::unique_ptr<LoadedScene> load(const std::string& spec, const PluginSpec& tracer);

// read_image with errors naming the option.
Image read_image_for(const std::string& option, const std::string& path);

struct ReferenceImage {
  Image image;
  std::string path;
  std::string kind;  // "cache" (read from the cache), "rendered" (rendered now into the cache), "file"
  uint64_t non_finite = 0;
  Image first_half;  // the first-half mean (shading/reference.h), empty when there is none
};
// The NoOpt reference's request for these settings: seed + kReferenceSeedOffset, --tracer, and with --device cuda the
// device (its own cache entry, shading/reference.h "Device") and the device trace kernel as its tracer; the device's
// frames are attached by render_reference_on_device (render_device.h) once the scene is loaded.
ReferenceRequest reference_request(const std::string& spec, const RenderCommon& c, int ref_frames,
                                   const std::string& cache_dir);
// "; GPU time X ms per frame (measured|simulated, on DEVICE)" of a device reference's rendered frames, "" when none.
std::string device_time_text(const DeviceTime& t);

// --reference when given (with its half image when "<stem>-half1<ext>" sits beside it), else the cached (or now
// rendered) NoOpt reference of shading/reference.h.
ReferenceImage obtain_reference(const LoadedScene& ls, const std::string& spec, const RenderCommon& c, int ref_frames,
                                const std::string& cache_dir, const std::string& explicit_path);

// The share of an error figure (NoiseCorrected::share) above which quality and converge warn that the reference's
// own noise is a large part of it.
constexpr double kNoiseWarnShare = 0.1;
// The reference's own noise (shading/metrics.h reference_noise, in the metric space of tm / space) from its half
// image, announced on stderr; nullopt, with the reason on stderr, when it has none.
std::optional<ReferenceNoise> noise_of_reference(const ReferenceImage& ref, const ToneMap& tm, MetricSpace space);
// The warning (stderr) when share > kNoiseWarnShare; `what` names the figure ("noopt", "noopt at frame 32").
void warn_reference_noise(const std::string& what, double share);

// "dir/name.csv" -> "dir/name".
std::string stem_path(const std::string& path);
// .png where this build writes PNG, else .pfm.
std::string display_extension();

}  // namespace raycoh
