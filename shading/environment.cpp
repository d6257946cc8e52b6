// Sky gradient, sun disc and sun-cone sampling (environment.h).
#include "shading/environment.h"

#include <algorithm>
#include <cmath>

namespace raycoh {

Vec3 sky_radiance(const Environment& env, Vec3 d) {
  if (!env.enabled) return Vec3(0.f);
  // +y is up (glTF); below the horizon the sky keeps the horizon colour (scenes close their floors).
  const float t = std::clamp(d.y, 0.f, 1.f);
  return env.sky_horizon * (1.f - t) + env.sky_zenith * t;
}

bool in_sun_cone(const Environment& env, Vec3 d) {
  return sun_on(env) && dot(d, env.sun_dir) >= env.sun_cos_half_angle;
}

Vec3 environment_radiance(const Environment& env, Vec3 d) {
  return sky_radiance(env, d) + (in_sun_cone(env, d) ? env.sun_radiance : Vec3(0.f));
}

bool sun_on(const Environment& env) {
  return env.enabled && max_component(env.sun_radiance) > 0.f && env.sun_cos_half_angle < 1.f;
}

float sun_cone_pdf(const Environment& env) {
  return static_cast<float>(1.0 / (2.0 * 3.14159265358979323846 * (1.0 - static_cast<double>(env.sun_cos_half_angle))));
}

SunSampler::SunSampler(const Environment& env)
    : on(sun_on(env)),
      pdf(on ? sun_cone_pdf(env) : 0.f),
      one_minus_cos(1.f - env.sun_cos_half_angle),
      frame(make_frame(env.sun_dir)) {}

Vec3 SunSampler::sample(float u, float v) const {
  const float one_minus = u * one_minus_cos;
  const float cos_t = 1.f - one_minus, sin_t = std::sqrt(std::max(0.f, one_minus * (2.f - one_minus)));
  float s, c;
  sincos_turns(v, s, c);
  return normalize(frame.to_world({sin_t * c, sin_t * s, cos_t}));
}

}  // namespace raycoh
