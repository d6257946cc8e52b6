// The camera ray of one pixel, one definition for make_primary_rays (CPU) and the CUDA primary kernel: a pinhole
// camera, or an orthographic one (Camera::ortho_half_height > 0: parallel rays from the plane through the eye).
#pragma once

#include <cmath>

#include "core/platform.h"
#include "core/ray.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "scenes/scene.h"

namespace raycoh {

// The camera basis and image plane, computed once per frame on the host.
struct PinholeCamera {
  Vec3 eye, forward, right, up;
  float tan_half = 0.f, aspect = 1.f;
  float ortho_half = 0.f;  // > 0: orthographic, the view's half-height
  int width = 0, height = 0;
};

inline PinholeCamera make_pinhole_camera(const Camera& camera, int width, int height) {
  PinholeCamera c;
  c.eye = camera.eye;
  c.forward = normalize(camera.target - camera.eye);
  c.right = normalize(cross(c.forward, camera.up));
  c.up = cross(c.right, c.forward);
  c.tan_half = std::tan(camera.vfov_deg * 0.5f * kPi / 180.f);
  c.aspect = static_cast<float>(width) / static_cast<float>(height);
  c.ortho_half = camera.ortho_half_height;
  c.width = width;
  c.height = height;
  return c;
}

// Vertical field of view, aspect = width / height, y = 0 at the top. With jitter, the sample position is uniform
// inside the pixel from rng(seed, frame, pixel, kDimPixelJitterX/Y); without, it is the pixel centre.
RAYCOH_HD RAYCOH_INLINE Ray primary_ray(const PinholeCamera& c, uint32_t p, uint32_t seed, uint32_t frame,
                                        bool jitter) {
  const auto width = static_cast<uint32_t>(c.width);
  const float jx = jitter ? rng_float(seed, frame, p, kDimPixelJitterX) : 0.5f;
  const float jy = jitter ? rng_float(seed, frame, p, kDimPixelJitterY) : 0.5f;
  const float ux = 2.f * ((static_cast<float>(p % width) + jx) / static_cast<float>(c.width)) - 1.f;
  const float uy = 1.f - 2.f * ((static_cast<float>(p / width) + jy) / static_cast<float>(c.height));
  Ray ray;
  if (c.ortho_half > 0.f) {
    ray.org = c.eye + c.right * (ux * c.ortho_half * c.aspect) + c.up * (uy * c.ortho_half);
    ray.dir = c.forward;
  } else {
    const float sx = ux * c.tan_half * c.aspect, sy = uy * c.tan_half;
    ray.org = c.eye;
    ray.dir = normalize(c.forward + c.right * sx + c.up * sy);
  }
  ray.tmin = 0.f;
  ray.tmax = __builtin_huge_valf();
  return ray;
}

}  // namespace raycoh
