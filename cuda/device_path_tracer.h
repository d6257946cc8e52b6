// The path tracer on the device (docs/design.md section 5; issue 43): the CPU path tracer's stages
// (shading/path_tracer.cpp) run as kernels over the same host/device functions for every BSDF, light and sampling
// decision (core/path_vertex.h, core/light_sampling.h, core/hit_surface.h, core/environment_light.h,
// core/bsdf.h), so that for the same seed it estimates the same image. Plain C++ (cuda/device_path_tracer.cpp).
//
// One frame:
//   1. camera rays in 8x8 tile order on the device (cuda/device_stages.h, make_primary_rays' rays), traced by
//      the device trace kernel; the hits are downloaded and the G-buffer made on the host by make_gbuffer (as the
//      device pipeline does, cuda/device_pipeline.h) and uploaded;
//   2. the first bounce's batch made by the device generator (cuda/device_generators.h, materialized: noopt,
//      ours, contiguous), equal to the CPU generator's batch bit for bit;
//   3. per bounce: next-event estimation, bounce sampling (later bounces), the wave traced and gathered
//      (cuda/device_shading.h), every batch traced by the device trace kernel (cuda/trace_kernels.h);
//   4. the frame's radiance downloaded (the caller accumulates it, e.g. into a shading/image.h Accumulator).
// Scene data (mesh, materials, textures, emitters, punctual lights, environment) is uploaded once, when the path
// tracer is made (cuda/device_scene_shading.h). Not on the device: the camera pass's G-buffer (host make_gbuffer,
// as in the device pipeline) and the accumulation. The fused first bounce (cuda:pipeline=fused) is not used here.
//
// frame_ms: CUDA events around the whole frame on the device's stream (camera rays to the last gather), which
// includes the device's idle time while the host makes the G-buffer and reads batch sizes: a measured GPU time on
// a GPU, a simulated one under GPGPU-Sim.
#pragma once

#include <memory>
#include <vector>

#include "core/light_sampling.h"
#include "core/ray_batch.h"
#include "cuda/device_shading.h"
#include "cuda/trace_kernels.h"
#include "scenes/scene.h"

namespace raycoh {
class Generator;
struct Bvh;
}  // namespace raycoh

namespace raycoh::cuda {

struct DeviceFrameStats {
  DeviceRayCounts rays;
  GenerationStats generation;
  float frame_ms = 0.f;  // CUDA events around the frame (see above)
};

// A DeviceTracer for scene's BVH2 with the scene's alpha MASK arrays (as the `cuda` tracer makes it).
std::unique_ptr<DeviceTracer> make_scene_device_tracer(const Scene& scene, const Bvh& bvh);

class DevicePathTracer {
 public:
  // scene, bvh and generator outlive the path tracer. host_lights: EmitterDistribution(scene).view(scene)
  // (shading/emitters.h, above this layer). Throws raycoh::Error when the generator has no device version
  // (check_gpu_generator) or on any CUDA error.
  DevicePathTracer(const Scene& scene, const Bvh& bvh, const LightsView& host_lights, const Generator& generator,
                   const DevicePathSettings& settings, const TraceLaunch& launch = {});
  ~DevicePathTracer();
  DevicePathTracer(const DevicePathTracer&) = delete;
  DevicePathTracer& operator=(const DevicePathTracer&) = delete;

  // Renders frame `frame` (one path per pixel): radiance[p] is its sample of pixel p (width x height entries).
  DeviceFrameStats render_frame(uint32_t frame, std::vector<Vec3>& radiance);
  // The last frame's first-bounce batch as the device generator made it.
  void download_first_bounce(RayBatch& out) const;
  const DevicePathSettings& settings() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace raycoh::cuda
