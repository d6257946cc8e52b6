// The environment light of scenes without emitters (docs/design.md section 6), written once for host and device:
// a sky gradient and a sun disc. Radiance lookups for rays that miss the scene, and the sun's cone as a light
// that next-event estimation samples (directions uniform in the cone, as pbrt-v4's SampleUniformCone). The sky is
// not sampled by NEE: it is smooth and dim, and BSDF sampling (cosine-weighted for diffuse surfaces) is already
// close to ideal for it, so a second strategy would only add shadow rays. The CPU path tracer
// (shading/environment.h) and the device one (cuda/device_shading.cu) call these same functions.
#pragma once

#include "core/platform.h"
#include "core/sampling.h"
#include "core/vec.h"

namespace raycoh {

// Sky + sun used when a scene has no emitter (or too weak an emitter to light it).
struct Environment {
  bool enabled = false;
  Vec3 sun_dir{0.3f, 0.9f, 0.3f};  // towards the sun; finalize_scene normalises it
  Vec3 sun_radiance{0.f, 0.f, 0.f};
  float sun_cos_half_angle = 0.99996f;  // half-angle 0.51 degrees, about 1 degree across
  Vec3 sky_zenith{0.f, 0.f, 0.f};
  Vec3 sky_horizon{0.f, 0.f, 0.f};
};

// std::clamp, std::max and std::min of floats as the standard defines them (NaN and signed zeros included), for
// host/device code that must give the bits the host code gave with <algorithm>.
RAYCOH_HD RAYCOH_INLINE float std_clamp(float v, float lo, float hi) { return v < lo ? lo : (hi < v ? hi : v); }
RAYCOH_HD RAYCOH_INLINE float std_max(float a, float b) { return a < b ? b : a; }
RAYCOH_HD RAYCOH_INLINE float std_min(float a, float b) { return b < a ? b : a; }

// Radiance of the sky gradient in direction d (unit); zero when the scene's environment is off.
RAYCOH_HD RAYCOH_INLINE Vec3 sky_radiance(const Environment& env, Vec3 d) {
  if (!env.enabled) return Vec3(0.f);
  // +y is up (glTF); below the horizon the sky keeps the horizon colour (scenes close their floors).
  const float t = std_clamp(d.y, 0.f, 1.f);
  return env.sky_horizon * (1.f - t) + env.sky_zenith * t;
}

// The sun as a light for next-event estimation: on only with an enabled environment, a positive radiance and a
// cone of non-zero size.
RAYCOH_HD RAYCOH_INLINE bool sun_on(const Environment& env) {
  return env.enabled && max_component(env.sun_radiance) > 0.f && env.sun_cos_half_angle < 1.f;
}

RAYCOH_HD RAYCOH_INLINE bool in_sun_cone(const Environment& env, Vec3 d) {
  return sun_on(env) && dot(d, env.sun_dir) >= env.sun_cos_half_angle;
}

// The sky gradient plus the sun's radiance inside its cone.
RAYCOH_HD RAYCOH_INLINE Vec3 environment_radiance(const Environment& env, Vec3 d) {
  return sky_radiance(env, d) + (in_sun_cone(env, d) ? env.sun_radiance : Vec3(0.f));
}

// Solid-angle pdf of a direction uniform in the sun's cone.
RAYCOH_HD RAYCOH_INLINE float sun_cone_pdf(const Environment& env) {
  return static_cast<float>(1.0 / (2.0 * 3.14159265358979323846 * (1.0 - static_cast<double>(env.sun_cos_half_angle))));
}

// Samples directions uniform in the sun's cone; built once per batch of shadow rays.
struct SunSampler {
  bool on = false;
  float pdf = 0.f;  // sun_cone_pdf, 0 when off
  float one_minus_cos = 0.f;
  Frame frame;  // around the sun direction
  SunSampler() = default;
  RAYCOH_HD explicit SunSampler(const Environment& env)
      : on(sun_on(env)),
        pdf(on ? sun_cone_pdf(env) : 0.f),
        one_minus_cos(1.f - env.sun_cos_half_angle),
        frame(make_frame(env.sun_dir)) {}
  // The direction for the uniform numbers u (polar, as 1 - cos) and v (azimuth, in turns).
  RAYCOH_HD Vec3 sample(float u, float v) const {
    const float one_minus = u * one_minus_cos;
    const float cos_t = 1.f - one_minus, sin_t = sqrtf(std_max(0.f, one_minus * (2.f - one_minus)));
    float s, c;
    sincos_turns(v, s, c);
    return normalize(frame.to_world({sin_t * c, sin_t * s, cos_t}));
  }
};

}  // namespace raycoh
