// Primary (camera) rays and the G-buffer of their first hits (traced by pipeline/first_hits.h).
#pragma once

#include <vector>

#include "core/ray.h"
#include "core/ray_batch.h"
#include "scenes/scene.h"

namespace raycoh {

// Rays with the pixel each belongs to: the camera rays of a frame, and the path tracer's bounce and shadow rays
// (make_gbuffer reads this type).
struct PixelRays {
  int width = 0, height = 0;
  uint32_t frame = 0;
  std::vector<Ray> rays;
  std::vector<uint32_t> pixel;  // y * width + x, y = 0 at the top of the image
};

// Pinhole camera (vertical field of view, aspect = width / height). With jitter, each pixel's sample position is
// uniform inside the pixel from rng(seed, frame, pixel, kDimPixelJitterX/Y); without, it is the pixel centre.
PixelRays make_primary_rays(const Camera& camera, int width, int height, const std::vector<uint32_t>& order,
                            uint32_t seed, uint32_t frame, bool jitter);

// Shading points of the hits (hits[i] belongs to primary.rays[i]).
GBuffer make_gbuffer(const Scene& scene, const PixelRays& primary, const std::vector<Hit>& hits);

}  // namespace raycoh
