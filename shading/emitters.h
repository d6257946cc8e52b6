// Emissive triangles as lights for next-event estimation: one triangle chosen with probability proportional to its
// power (area x luminance of its emission), then a uniform point on it (Shirley's square-root map, as pbrt-v4's
// SampleUniformTriangle). Emission is one-sided: the front side of the triangle's winding, as in pbrt and Mitsuba.
//
// The probability of each triangle is the exact probability that pick() returns it for a uniform number on
// rng_float's grid of 2^-24 steps, so NEE and the MIS weights of BSDF hits use the same number even for triangles
// too dim to be picked at all (probability 0: then only BSDF sampling finds them, with weight 1).
#pragma once

#include <cstdint>
#include <vector>

#include "core/ray_batch.h"
#include "scenes/scene.h"

namespace raycoh {

// A point on an emitter seen from a shading point.
struct EmitterSample {
  bool found = false;  // false: no light from this sample (degenerate, or the point sees the emitter's back)
  Vec3 dir;            // unit, from the offset ray origin towards the point
  float dist = 0.f;    // from the offset ray origin to the point
  float pdf = 0.f;     // solid angle, triangle choice included
  Vec3 emission;
};

struct EmitterDistribution {
  std::vector<uint32_t> tris;
  std::vector<float> cdf;          // inclusive, last = 1
  std::vector<float> pmf_by_prim;  // probability of picking triangle prim (0 for non-emitters), sized per triangle
  std::vector<float> area_by_prim;

  explicit EmitterDistribution(const Scene& scene);
  bool empty() const { return tris.empty(); }
  // The first triangle whose cdf entry exceeds u (u in [0, 1)).
  size_t pick(float u) const;
  // A point on an emitter for the uniform numbers u_pick (which triangle), u and v (where on it), seen from sp.
  EmitterSample sample(const Scene& scene, const ShadingPoint& sp, float u_pick, float u, float v) const;
  // Solid-angle pdf with which sample() finds emitter prim at distance dist and cosine cos_y on its side.
  float pdf(uint32_t prim, float dist, float cos_y) const {
    return pmf_by_prim[prim] / area_by_prim[prim] * dist * dist / cos_y;
  }
};

}  // namespace raycoh
