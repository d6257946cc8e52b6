// The device path tracer's frame loop (cuda/device_path_tracer.h): camera pass, first bounce from the device
// generator, then per bounce next-event estimation, bounce sampling and hit gathering on the device.
#include "cuda/device_path_tracer.h"

#include <fmt/format.h>

#include <utility>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "cuda/device_gbuffer.h"
#include "cuda/device_generators.h"
#include "cuda/device_scene_shading.h"
#include "cuda/device_stages.h"
#include "cuda/stage_clock.h"
#include "generators/generator.h"

namespace raycoh::cuda {

namespace {

constexpr int kPrimaryTile = 8;  // the CPU path tracer's camera-ray order (shading/path_tracer.cpp)

// The frame's stages on its StageClock (DeviceFrameStages, in this order); the trace kernels of the first and
// second bounces' waves have stages of their own (DeviceFrameStages::trace_ms holds them too).
enum Stage : int { kCamera, kGeneration, kNextEvent, kSample, kTrace, kGather, kTraceFirst, kTraceSecond, kStages };

}  // namespace

AlphaMaskArrays scene_alpha_arrays(const Scene& scene) {
  AlphaMaskArrays alpha;
  if (scene.alpha.empty()) return alpha;
  const AlphaMasks& a = scene.alpha;
  RAYCOH_CHECK(a.tri_uv.size() == 6 * a.tri_texture.size(),
               fmt::format("scene '{}': {} alpha uv values for {} triangles", scene.name, a.tri_uv.size(),
                           a.tri_texture.size()));
  alpha.tri_texture = a.tri_texture.data();
  alpha.tri_uv = a.tri_uv.data();
  alpha.tri_count = a.tri_texture.size();
  alpha.textures = a.textures.data();
  alpha.texture_count = a.textures.size();
  alpha.texels = a.texels.data();
  alpha.texel_count = a.texels.size();
  return alpha;
}

std::unique_ptr<DeviceTracer> make_scene_device_tracer(const Scene& scene, const Bvh& bvh) {
  return std::make_unique<DeviceTracer>(bvh.view(), scene_alpha_arrays(scene));
}

struct DevicePathTracer::Impl {
  const Scene& scene;
  const Generator& generator;
  DevicePathSettings settings;
  TraceLaunch launch;
  std::unique_ptr<DeviceTracer> tracer;
  DeviceSceneShading shading_scene;
  DeviceShading shading;
  DeviceStages stages;
  DeviceGBuffer gbuffer;
  DeviceGenerator device_generator;
  StageClock clock{kStages};

  Impl(const Scene& s, const Bvh& bvh, const LightsView& lights, const Generator& g, const DevicePathSettings& ps,
       const TraceLaunch& l)
      : scene(s),
        generator(g),
        settings(ps),
        launch(l),
        tracer(make_scene_device_tracer(s, bvh)),
        shading_scene(s, lights),
        shading(shading_scene, *tracer, l, ps),
        gbuffer(s, shading_scene.view().mesh),
        device_generator(s) {
    shading.set_clock(&clock, TraceStages{kTrace, kTraceFirst, kTraceSecond});
  }

  // Camera rays on the device, traced; their G-buffer made on the device (only its hit count is read back).
  void camera(uint32_t frame) {
    clock.start(kCamera);
    stages.launch_primary(scene.camera, settings.width, settings.height, kPrimaryTile, kPrimaryTile, settings.seed,
                          frame, true);
    const size_t n = stages.primary_count();
    Hit* hits = stages.hits(n);
    clock.enter(kTrace);
    tracer->trace_device(stages.primary_rays(), nullptr, n, hits, launch);
    clock.enter(kCamera);
    gbuffer.launch(stages.primary_rays(), stages.primary_pixels(), hits, n, settings.width, settings.height, frame);
    shading.camera(frame, gbuffer.finish(), stages.primary_rays(), stages.primary_pixels(), hits, n);
  }

  // The first wave: the device generator's batch over the device G-buffer, traced by the trace kernel in gather;
  // fused: made and traced in one kernel per tile, which also writes the batch for the wave's shading (the
  // kernel, and the tile offsets before it, count as trace).
  void first_bounce(GenerationStats& stats) {
    device_generator.use_device(gbuffer.view());
    const size_t n = device_generator.device_count();
    if (settings.fused) {
      const int was = clock.enter(kTraceFirst);
      device_generator.launch_fused(settings.seed, generator, *tracer, launch, shading.first_wave_hits(n), true);
      clock.enter(was);
    } else {
      device_generator.launch(settings.seed, generator);
    }
    device_generator.finish(stats);
    shading.first_bounce(device_generator.device_batch(), n, settings.fused);
  }

  DeviceFrameStages stage_times() const {
    float ms[kStages];
    clock.wait_ms(ms);
    DeviceFrameStages t;
    t.camera_ms = ms[kCamera];
    t.generation_ms = ms[kGeneration];
    t.next_event_ms = ms[kNextEvent];
    t.sample_ms = ms[kSample];
    t.trace_ms = ms[kTrace] + ms[kTraceFirst] + ms[kTraceSecond];
    t.gather_ms = ms[kGather];
    t.first_wave_trace_ms = ms[kTraceFirst];
    t.second_wave_trace_ms = ms[kTraceSecond];
    return t;
  }
};

DevicePathTracer::DevicePathTracer(const Scene& scene, const Bvh& bvh, const LightsView& host_lights,
                                   const Generator& generator, const DevicePathSettings& settings,
                                   const TraceLaunch& launch) {
  if (settings.width < 1 || settings.height < 1 || settings.max_depth < 1 || settings.rr_depth < 1)
    throw Error("device path tracer: width, height, max depth and roulette depth must be positive");
  check_gpu_generator(generator, settings.fused);
  impl_ = std::make_unique<Impl>(scene, bvh, host_lights, generator, settings, launch);
}

DevicePathTracer::~DevicePathTracer() = default;

DeviceFrameStats DevicePathTracer::render_frame(uint32_t frame, std::vector<Vec3>& radiance) {
  Impl& d = *impl_;
  DeviceFrameStats stats;
  bool made_first = false;
  d.stages.start_span();
  d.camera(frame);
  for (int bounce = 0; bounce < d.settings.max_depth && d.shading.vertices() > 0; ++bounce) {
    d.clock.enter(kNextEvent);
    d.shading.next_event(bounce);
    if (bounce == 0) {
      d.clock.enter(kGeneration);
      d.first_bounce(stats.generation);
      made_first = true;
    } else {
      d.clock.enter(kSample);
      d.shading.sample(bounce);
    }
    d.clock.enter(kGather);
    d.shading.gather(bounce);
  }
  d.clock.stop();
  d.stages.stop_span();
  stats.frame_ms = d.stages.wait_span_ms();
  stats.stages = d.stage_times();
  stats.rays = d.shading.counts();
  // After the frame's span, so not in its time: the first-bounce batch stays the generator's until its next launch.
  stats.hybrid_diffuse = made_first ? d.device_generator.count_hybrid_diffuse() : 0;
  d.shading.download_radiance(radiance);
  return stats;
}

void DevicePathTracer::download_first_bounce(RayBatch& out) const { impl_->device_generator.download(out); }

void DevicePathTracer::download_camera(PixelRays& rays, std::vector<Hit>& hits) const {
  impl_->stages.download_primary(rays);
  impl_->stages.download_hits(hits, impl_->stages.primary_count());
}

GBuffer DevicePathTracer::download_gbuffer() const { return impl_->gbuffer.download(); }

const DevicePathSettings& DevicePathTracer::settings() const { return impl_->settings; }

}  // namespace raycoh::cuda
