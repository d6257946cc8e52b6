// The device buffers and stage timers of the device pipeline (cuda/device_pipeline.h) that are not a generator's,
// an encoder's or the tracer's own (implemented in cuda/device_stages.cu; plain C++ header): the camera rays, the
// physically permuted batch and its gather kernel, the hits, and the event pairs of the primary-ray, permute and
// whole-pass (span) stages. Every launch is queued on the default stream and waits for nothing; the wait_*
// calls wait for their stop event. Throws raycoh::Error on any CUDA error.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/batch_view.h"
#include "core/ray.h"
#include "core/ray_batch.h"
#include "generators/primary.h"
#include "scenes/scene.h"

namespace raycoh::cuda {

class DeviceStages {
 public:
  DeviceStages();
  ~DeviceStages();
  DeviceStages(const DeviceStages&) = delete;
  DeviceStages& operator=(const DeviceStages&) = delete;

  // Camera rays in tile order (make_primary_rays_gpu's), between the primary timer's events.
  void launch_primary(const Camera& camera, int width, int height, int tile_w, int tile_h, uint32_t seed,
                      uint32_t frame, bool jitter);
  const Ray* primary_rays() const;
  const uint32_t* primary_pixels() const;  // pixel of each camera ray, on the device
  size_t primary_count() const;
  float wait_primary_ms() const;
  void download_primary(PixelRays& out) const;

  // The physical permutation: element i of every array `in` has (tile, group and group_type only when `in` has
  // them) is element d_order[i] of it, as encoders/permute.h permute_batch does on the CPU; between the permute
  // timer's events. Returns the permuted batch's arrays on the device.
  BatchView launch_gather(const BatchView& in, const uint32_t* d_order, size_t n);
  float wait_permute_ms() const;
  // The last gather's n rays (width, height and frame are the caller's).
  void download_permuted(RayBatch& out, size_t n) const;

  // Room for n hits on the device (grown on demand); download_hits copies the first n.
  Hit* hits(size_t n);
  void download_hits(std::vector<Hit>& out, size_t n) const;

  // The whole-pass event pair (DeviceStageTimes::span_ms).
  void start_span();
  void stop_span();
  float wait_span_ms() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace raycoh::cuda
