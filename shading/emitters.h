// Emissive triangles as lights for next-event estimation: one triangle chosen with probability proportional to its
// power (area x luminance of its emission), then a uniform point on it (Shirley's square-root map, as pbrt-v4's
// SampleUniformTriangle). Emission is one-sided: the front side of the triangle's winding, as in pbrt and Mitsuba.
//
// The probability of each triangle is the exact probability that pick() returns it for a uniform number on
// rng_float's grid of 2^-24 steps, so NEE and the MIS weights of BSDF hits use the same number even for triangles
// too dim to be picked at all (probability 0: then only BSDF sampling finds them, with weight 1).
//
// Punctual lights (glTF KHR_lights_punctual, scenes/scene.h) are delta lights: BSDF sampling cannot find them, so
// next-event estimation is their only strategy (MIS weight 1). One light is chosen per shading point with
// probability proportional to its power, as pbrt-v4's PowerLightSampler: point 4 pi I, spot
// 2 pi I (1 - (cos_inner + cos_outer) / 2), directional pi r^2 E with r the radius of the scene's bounding sphere
// (luminance of the colour), with the same exact grid probabilities. What a light delivers follows the glTF spec:
// I / d^2 for point and spot lights, times the spot's smooth cone falloff
// t = clamp((cos - cos_outer) / max(1e-3, cos_inner - cos_outer), 0, 1), squared, and, where a range is given,
// the spec's recommended window clamp(1 - (d / range)^4, 0, 1); E for directional lights.
#pragma once

#include <cstdint>
#include <vector>

#include "core/light_sampling.h"
#include "core/ray_batch.h"
#include "scenes/scene.h"

namespace raycoh {

// EmitterSample, PunctualSample and the sampling functions themselves: core/light_sampling.h.

struct PunctualLights {
  std::vector<float> cdf;                 // inclusive, last = 1
  std::vector<float> pmf;                 // exact probability of picking each light
  std::vector<PunctualLightView> lights;  // the scene's lights as the sampling functions read them
  explicit PunctualLights(const Scene& scene);
  bool empty() const { return cdf.empty(); }
  // The light for the uniform number u_pick, seen from sp.
  PunctualSample sample(const Scene& scene, const ShadingPoint& sp, float u_pick) const;
};

// What light l delivers at distance d along unit direction dir (from the light towards the point): I / d^2 with
// the spot cone and range windows for point and spot lights (d unused for directional lights: E).
Vec3 punctual_irradiance(const PunctualLight& l, Vec3 dir, float d);
PunctualLightView punctual_view(const PunctualLight& l);

struct EmitterDistribution {
  std::vector<uint32_t> tris;
  std::vector<float> cdf;          // inclusive, last = 1
  std::vector<float> pmf_by_prim;  // probability of picking triangle prim (0 for non-emitters), sized per triangle
  std::vector<float> area_by_prim;
  PunctualLights punctual;                  // the scene's punctual lights, sampled apart from the triangles
  std::vector<Vec3> material_emission;      // per scene material (LightsView)
  std::vector<MaterialClass> material_cls;  // per scene material (LightsView's mesh)

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
  // Every array of the distribution and of `scene` (which must be the scene it was made from) that sampling reads,
  // as host pointers (core/light_sampling.h); valid while both live.
  LightsView view(const Scene& scene) const;
};

}  // namespace raycoh
