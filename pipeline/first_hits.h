// The host camera pass: a frame's camera rays (generators/primary.h), traced by a Tracer, and the G-buffer of their
// first hits. It lives above tracers/ because it traces; generators/ makes rays and never includes a tracer. The
// same pass on a tracer's own device is DevicePipeline::primary (tracers/device_pipeline.h).
#pragma once

#include <cstdint>
#include <vector>

#include "core/ray.h"
#include "core/ray_batch.h"
#include "generators/primary.h"
#include "scenes/scene.h"

namespace raycoh {

class Tracer;

// One frame's first hits: the camera rays in `order`, their closest hits and the G-buffer made from them.
struct FirstHits {
  PixelRays primary;
  std::vector<Hit> hits;  // hits[i] belongs to primary.rays[i]
  GBuffer gbuffer;
  double trace_seconds = 0.0;  // wall-clock time of the tracer call alone
};

// order -> primary rays -> trace -> G-buffer: the one way every command, benchmark and test gets its first hits.
FirstHits first_hits(const Scene& scene, Tracer& tracer, int width, int height, const std::vector<uint32_t>& order,
                     uint32_t seed, uint32_t frame, bool jitter = true);

}  // namespace raycoh
