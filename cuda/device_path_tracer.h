// The path tracer on the device (docs/design.md section 5; issue 43): the CPU path tracer's stages
// (shading/path_tracer.cpp) run as kernels over the same host/device functions for every BSDF, light and sampling
// decision (core/path_vertex.h, core/light_sampling.h, core/hit_surface.h, core/environment_light.h,
// core/bsdf.h), so that for the same seed it estimates the same image. Plain C++ (cuda/device_path_tracer.cpp).
//
// One frame:
//   1. camera rays in 8x8 tile order on the device (cuda/device_stages.h, make_primary_rays' rays), traced by
//      the device trace kernel; their G-buffer made on the device by the G-buffer kernel (cuda/device_gbuffer.h:
//      make_gbuffer's hit_surface per hit, equal to make_gbuffer bit for bit) and kept there: only its hit count
//      comes to the host (download_gbuffer copies the rest where a caller asks for it);
//   2. the first bounce's batch made by the device generator (cuda/device_generators.h: noopt, ours, contiguous,
//      sadeghi, microjitter), equal to the CPU generator's batch bit for bit; materialized (the batch written,
//      then traced by the trace kernel) or, with settings.fused (cuda:pipeline=fused; all five, ours and
//      contiguous in tile or group order),
//      made and traced in one kernel per tile that reads each ray from shared memory and also writes the batch
//      for the wave's shading (cuda/fused_kernels.cu): the same rays and hits;
//   3. per bounce: next-event estimation, bounce sampling (later bounces), the wave traced and gathered
//      (cuda/device_shading.h), every batch traced by the device trace kernel (cuda/trace_kernels.h);
//   4. the frame's radiance downloaded (the caller accumulates it, e.g. into a shading/image.h Accumulator).
// Scene data (mesh, materials, textures, emitters, punctual lights, environment) is uploaded once, when the path
// tracer is made (cuda/device_scene_shading.h). Not on the device: the accumulation.
//
// frame_ms: CUDA events around the whole frame on the device's stream (camera rays to the last gather), which
// includes the device's idle time while the host reads counts and batch sizes and launches: a measured GPU time
// on a GPU, a simulated one under GPGPU-Sim. stages: the same span cut at the stages' boundaries by events on the
// same stream (cuda/stage_clock.h), read at the frame's end with frame_ms, so no synchronisation is added.
#pragma once

#include <memory>
#include <vector>

#include "core/light_sampling.h"
#include "core/ray_batch.h"
#include "cuda/device_shading.h"
#include "cuda/trace_kernels.h"
#include "generators/primary.h"
#include "scenes/scene.h"

namespace raycoh {
class Generator;
struct Bvh;
}  // namespace raycoh

namespace raycoh::cuda {

// Per-stage device times of a frame in ms: the frame from its camera rays to its last gather cut at the stages'
// boundaries, each interval counted for the stage it lies in (the device's idle time inside a stage included), so
// the stages add up to at most frame_ms (up to the events' resolution).
struct DeviceFrameStages {
  float camera_ms = 0.f;      // camera rays, the G-buffer kernel and its hit count, camera shading, compaction
  float generation_ms = 0.f;  // first bounce: the device generator and its batch made the first wave (fused: the
                              // wave only; the kernel that makes and traces the rays counts as trace)
  float next_event_ms = 0.f;  // next-event estimation: shadow rays made, resolved, added (not their traces)
  float sample_ms = 0.f;      // bounce sampling of the later bounces, compaction
  float trace_ms = 0.f;       // every trace kernel: camera rays, shadow rounds, waves
  float gather_ms = 0.f;      // each wave's hits shaded, its light added, the next vertices compacted
  float sum_ms() const { return camera_ms + generation_ms + next_event_ms + sample_ms + trace_ms + gather_ms; }
  // Of trace_ms: the trace kernel of the first bounce's wave (fused: the kernel that makes and traces it) and of
  // the second bounce's wave (rays.secondary and rays.second rays), so that their trace speeds can be compared.
  float first_wave_trace_ms = 0.f, second_wave_trace_ms = 0.f;
};

struct DeviceFrameStats {
  DeviceRayCounts rays;
  GenerationStats generation;
  float frame_ms = 0.f;      // CUDA events around the frame (see above)
  DeviceFrameStages stages;  // frame_ms by stage (see above)
  // First-bounce rays of a hybrid group whose own class is diffuse (the CPU's FrameStats::hybrid_diffuse), counted
  // after the frame's span (not in frame_ms).
  uint64_t hybrid_diffuse = 0;
};

// The scene's alpha MASK arrays (Scene::alpha) as the DeviceTracer takes them (empty when the scene has none);
// they point into the scene. Throws raycoh::Error when its uv arrays do not match its triangles.
AlphaMaskArrays scene_alpha_arrays(const Scene& scene);
// A DeviceTracer for scene's BVH2 with the scene's alpha MASK arrays (as the `cuda` tracer makes it).
std::unique_ptr<DeviceTracer> make_scene_device_tracer(const Scene& scene, const Bvh& bvh);

class DevicePathTracer {
 public:
  // scene, bvh and generator outlive the path tracer. host_lights: EmitterDistribution(scene).view(scene)
  // (shading/emitters.h, above this layer). Throws raycoh::Error when the generator has no device version
  // (check_gpu_generator; with settings.fused, no fused form) or on any CUDA error.
  DevicePathTracer(const Scene& scene, const Bvh& bvh, const LightsView& host_lights, const Generator& generator,
                   const DevicePathSettings& settings, const TraceLaunch& launch = {});
  ~DevicePathTracer();
  DevicePathTracer(const DevicePathTracer&) = delete;
  DevicePathTracer& operator=(const DevicePathTracer&) = delete;

  // Renders frame `frame` (one path per pixel): radiance[p] is its sample of pixel p (width x height entries).
  DeviceFrameStats render_frame(uint32_t frame, std::vector<Vec3>& radiance);
  // The last frame's first-bounce batch as the device generator made it.
  void download_first_bounce(RayBatch& out) const;
  // The last frame's camera rays and their hits, and the G-buffer the device made of them (with its table).
  void download_camera(PixelRays& rays, std::vector<Hit>& hits) const;
  GBuffer download_gbuffer() const;
  const DevicePathSettings& settings() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace raycoh::cuda
