// The stages of one path-traced frame on the device (cuda/device_shading.cu; plain C++ header): the device
// path tracer's (cuda/device_path_tracer.h) counterpart of the CPU path tracer's stages (shading/path_stages.h),
// each a kernel over the same host/device functions of core/path_vertex.h, core/light_sampling.h,
// core/hit_surface.h, core/environment_light.h and core/bsdf.h that the CPU stages call:
//   camera        the camera rays' hits (their G-buffer made on the device, cuda/device_gbuffer.h, read where it
//                 lies): emitters and environment seen directly; the first path vertices
//   next_event    two shadow rays per non-delta vertex (slots 2i, 2i + 1), traced in rounds through thin panes
//   first_bounce  the generator's batch (already on the device) as the first wave; its hits too when the first
//                 bounce was fused (made and traced in one kernel)
//   sample        BSDF-sampled directions of later bounces, Russian roulette
//   gather        the wave traced; light found by it; the hits become the next vertices
// Every array is per ray or per vertex and compacted in a fixed order (a prefix sum over keep flags), every
// pixel's radiance is added by one thread at a time in the CPU's order (camera, each shadow round slot by slot,
// each wave), so a frame is the same bits on every run. Batches are traced by the device trace kernels
// (cuda/trace_kernels.h DeviceTracer::trace_device). Throws raycoh::Error on any CUDA error.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/batch_view.h"
#include "core/path_vertex.h"
#include "core/ray.h"
#include "core/ray_batch.h"
#include "cuda/device_gbuffer.h"
#include "cuda/device_scene_shading.h"
#include "cuda/stage_clock.h"
#include "cuda/trace_kernels.h"

namespace raycoh::cuda {

// What a frame of the device path tracer needs besides the scene: core/path_vertex.h's inputs.
struct DevicePathSettings {
  int width = 160, height = 120;
  uint32_t seed = 1;
  int max_depth = 5;
  int rr_depth = 3;
  // The first bounce made and traced in one kernel per tile (cuda:pipeline=fused, cuda/fused_kernels.cu) instead
  // of a materialized batch traced by the trace kernel; the same rays, hits and image bit for bit.
  bool fused = false;
};

// Rays traced by one frame, by kind (as FrameStats of shading/path_tracer.h counts them).
struct DeviceRayCounts {
  uint64_t primary = 0, secondary = 0, bounce = 0, shadow = 0;
  uint64_t second = 0;  // of `bounce`: the second bounce's wave (the rays leaving the first bounce's hits)
};

// The clock stages a DeviceShading's traces run as (set_clock): the first and second bounces' waves each have a
// stage of their own, so that their trace speeds can be told apart; every other trace runs as `other`.
struct TraceStages {
  int other = 0, first_wave = 0, second_wave = 0;
};

class DeviceShading {
 public:
  // scene and tracer outlive this object.
  DeviceShading(const DeviceSceneShading& scene, DeviceTracer& tracer, const TraceLaunch& launch,
                const DevicePathSettings& settings);
  ~DeviceShading();
  DeviceShading(const DeviceShading&) = delete;
  DeviceShading& operator=(const DeviceShading&) = delete;

  // Every trace from now on runs as a stage of clock (cuda/stage_clock.h; null: no clock), handing the time back
  // to the stage that was current: the first and second bounces' waves as theirs, the rest as stages.other.
  void set_clock(StageClock* clock, const TraceStages& stages);
  // Camera pass of frame `frame`: every pixel's radiance is set from its camera ray (d_rays[i] of pixel
  // d_pixels[i], hit d_hits[i], n = width x height; device arrays), the vertices are its hits, in ray order.
  // gbuffer: the G-buffer of those rays and hits on the device (DeviceGBuffer), read there until the next camera
  // pass (points and material table; it must stay unchanged until then).
  void camera(uint32_t frame, const DeviceGBufferView& gbuffer, const Ray* d_rays, const uint32_t* d_pixels,
              const Hit* d_hits, size_t n);
  size_t vertices() const;
  // Next-event estimation at the vertices of bounce b (their shadow rays traced here).
  void next_event(int bounce);
  // The first wave: the generator's batch on the device (n rays; rays, pixel, pdf, weight, material). traced: its
  // hits are already in first_wave_hits(n) (a fused first bounce), so gather(0) does not trace it again.
  void first_bounce(const BatchView& batch, size_t n, bool traced = false);
  // Where a fused first bounce writes the hits of its n rays (valid until the next trace).
  Hit* first_wave_hits(size_t n);
  // The wave leaving the vertices of bounce b (b >= 1).
  void sample(int bounce);
  // Traces the wave of bounce b, adds the light it finds, and makes the hits the next vertices.
  void gather(int bounce);
  // The frame's radiance per pixel (width x height), downloaded.
  void download_radiance(std::vector<Vec3>& out) const;
  const DeviceRayCounts& counts() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace raycoh::cuda
