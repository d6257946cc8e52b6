// The environment light of scenes without emitters (docs/design.md section 6): a sky gradient and a sun disc.
// Radiance lookups for rays that miss the scene, and the sun's cone as a light that next-event estimation samples
// (directions uniform in the cone, as pbrt-v4's SampleUniformCone). The sky is not sampled by NEE: it is smooth
// and dim, and BSDF sampling (cosine-weighted for diffuse surfaces) is already close to ideal for it, so a second
// strategy would only add shadow rays.
#pragma once

#include "core/sampling.h"
#include "scenes/scene.h"

namespace raycoh {

// Radiance of the environment in direction d (unit): the sky gradient, plus the sun's radiance inside its cone.
// Zero when the scene's environment is off.
Vec3 sky_radiance(const Environment& env, Vec3 d);
bool in_sun_cone(const Environment& env, Vec3 d);
Vec3 environment_radiance(const Environment& env, Vec3 d);

// The sun as a light for next-event estimation: on only with an enabled environment, a positive radiance and a
// cone of non-zero size.
bool sun_on(const Environment& env);
// Solid-angle pdf of a direction uniform in the sun's cone.
float sun_cone_pdf(const Environment& env);

// Samples directions uniform in the sun's cone; built once per batch of shadow rays.
struct SunSampler {
  bool on = false;
  float pdf = 0.f;  // sun_cone_pdf, 0 when off
  float one_minus_cos = 0.f;
  Frame frame;  // around the sun direction
  explicit SunSampler(const Environment& env);
  // The direction for the uniform numbers u (polar, as 1 - cos) and v (azimuth, in turns).
  Vec3 sample(float u, float v) const;
};

}  // namespace raycoh
