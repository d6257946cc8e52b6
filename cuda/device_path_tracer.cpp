// The device path tracer's frame loop (cuda/device_path_tracer.h): camera pass, first bounce from the device
// generator, then per bounce next-event estimation, bounce sampling and hit gathering on the device.
#include "cuda/device_path_tracer.h"

#include <utility>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "cuda/device_generators.h"
#include "cuda/device_scene_shading.h"
#include "cuda/device_stages.h"
#include "generators/generator.h"
#include "generators/primary.h"

namespace raycoh::cuda {

namespace {

constexpr int kPrimaryTile = 8;  // the CPU path tracer's camera-ray order (shading/path_tracer.cpp)

}  // namespace

std::unique_ptr<DeviceTracer> make_scene_device_tracer(const Scene& scene, const Bvh& bvh) {
  AlphaMaskArrays alpha;
  if (!scene.alpha.empty()) {
    const AlphaMasks& a = scene.alpha;
    RAYCOH_CHECK(a.tri_uv.size() == 6 * a.tri_texture.size(), "alpha uv arrays do not match the triangles");
    alpha.tri_texture = a.tri_texture.data();
    alpha.tri_uv = a.tri_uv.data();
    alpha.tri_count = a.tri_texture.size();
    alpha.textures = a.textures.data();
    alpha.texture_count = a.textures.size();
    alpha.texels = a.texels.data();
    alpha.texel_count = a.texels.size();
  }
  return std::make_unique<DeviceTracer>(bvh.view(), alpha);
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
  DeviceGenerator device_generator;

  Impl(const Scene& s, const Bvh& bvh, const LightsView& lights, const Generator& g, const DevicePathSettings& ps,
       const TraceLaunch& l)
      : scene(s),
        generator(g),
        settings(ps),
        launch(l),
        tracer(make_scene_device_tracer(s, bvh)),
        shading_scene(s, lights),
        shading(shading_scene, *tracer, l, ps),
        device_generator(s) {}

  // Camera rays on the device, traced; the G-buffer made on the host from the downloaded hits and uploaded.
  GBuffer camera(uint32_t frame) {
    stages.launch_primary(scene.camera, settings.width, settings.height, kPrimaryTile, kPrimaryTile, settings.seed,
                          frame, true);
    const size_t n = stages.primary_count();
    Hit* hits = stages.hits(n);
    tracer->trace_device(stages.primary_rays(), nullptr, n, hits, launch);
    PixelRays rays;
    std::vector<Hit> host_hits;
    stages.download_primary(rays);
    stages.download_hits(host_hits, n);
    GBuffer gbuffer = make_gbuffer(scene, rays, host_hits);
    shading.camera(frame, gbuffer, stages.primary_rays(), stages.primary_pixels(), hits, n);
    return gbuffer;
  }
};

DevicePathTracer::DevicePathTracer(const Scene& scene, const Bvh& bvh, const LightsView& host_lights,
                                   const Generator& generator, const DevicePathSettings& settings,
                                   const TraceLaunch& launch) {
  if (settings.width < 1 || settings.height < 1 || settings.max_depth < 1 || settings.rr_depth < 1)
    throw Error("device path tracer: width, height, max depth and roulette depth must be positive");
  check_gpu_generator(generator);
  impl_ = std::make_unique<Impl>(scene, bvh, host_lights, generator, settings, launch);
}

DevicePathTracer::~DevicePathTracer() = default;

DeviceFrameStats DevicePathTracer::render_frame(uint32_t frame, std::vector<Vec3>& radiance) {
  Impl& d = *impl_;
  DeviceFrameStats stats;
  d.stages.start_span();
  const GBuffer gbuffer = d.camera(frame);
  for (int bounce = 0; bounce < d.settings.max_depth && d.shading.vertices() > 0; ++bounce) {
    d.shading.next_event(bounce);
    if (bounce == 0) {
      d.device_generator.upload(gbuffer);
      d.device_generator.launch(d.settings.seed, d.generator);
      d.device_generator.finish(stats.generation);
      d.shading.first_bounce(d.device_generator.device_batch(), d.device_generator.device_count());
    } else {
      d.shading.sample(bounce);
    }
    d.shading.gather(bounce);
  }
  d.stages.stop_span();
  stats.frame_ms = d.stages.wait_span_ms();
  stats.rays = d.shading.counts();
  d.shading.download_radiance(radiance);
  return stats;
}

void DevicePathTracer::download_first_bounce(RayBatch& out) const { impl_->device_generator.download(out); }

const DevicePathSettings& DevicePathTracer::settings() const { return impl_->settings; }

}  // namespace raycoh::cuda
