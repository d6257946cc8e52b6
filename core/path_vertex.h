// The decisions of the path tracer at one path vertex or one ray, written once for host and device: the CPU
// stages (shading/next_event.cpp, bounce_sampling.cpp, hit_gathering.cpp) and the device path tracer's kernels
// (cuda/device_shading.cu) call these functions, so both run the same estimator. The method is in
// shading/path_tracer.cpp's doc block; each function names the stage it is a step of.
//
// Random numbers of the vertex of bounce b: rng(seed, frame, pixel, kDimFirstFree + 16 b + k) (the generator uses
// its own dimensions, core/rng.h, for the first bounce).
#pragma once

#include "core/bsdf.h"
#include "core/environment_light.h"
#include "core/light_sampling.h"
#include "core/platform.h"
#include "core/ray.h"
#include "core/ray_batch.h"
#include "core/rng.h"

namespace raycoh {

constexpr uint32_t kDimsPerBounce = 16;
enum BounceDim : uint32_t {
  kEmitterPick = 0,
  kEmitterU = 1,
  kEmitterV = 2,
  kSunU = 3,
  kSunV = 4,
  kDirU = 5,
  kDirV = 6,
  kLobe = 7,
  kRoulette = 8,
  kLightPick = 9
};

// The uniform number k of pixel p's vertex of bounce b.
RAYCOH_HD RAYCOH_INLINE float bounce_rand(uint32_t seed, uint32_t frame, uint32_t p, int bounce, BounceDim k) {
  return rng_float(seed, frame, p, kDimFirstFree + kDimsPerBounce * static_cast<uint32_t>(bounce) + k);
}

// Power heuristic (beta = 2) weight of the strategy with pdf a against b, written so that it never divides
// infinities: 1 / (1 + (b/a)^2).
RAYCOH_HD RAYCOH_INLINE float power_heuristic(float a, float b) {
  if (!(a > 0.f)) return 0.f;
  const float r = b / a;
  return 1.f / (1.f + r * r);
}

// Transmissive surfaces are a smooth dielectric: delta lobes only, so no NEE there and MIS weight 1 after them.
RAYCOH_HD RAYCOH_INLINE bool is_delta(MaterialClass c) { return c == MaterialClass::Transmissive; }
RAYCOH_HD RAYCOH_INLINE bool is_thin_pane(const BsdfParams& m) {
  return m.cls == MaterialClass::Transmissive && m.thin_walled;
}

// How the light a ray finds is weighted (MIS state): the pdf and delta flag of the direction chosen at the last
// scattering event that was not a straight pass through a thin pane, and the distance travelled since that event
// before this ray's origin (the light pdf of an emitter is measured from there).
struct MisState {
  float pdf = 0.f;
  uint8_t delta = 1;  // a camera ray: nothing else could have found the light
  float dist = 0.f;
};

// Radiance a shading point with emission le (its material entry's) emits towards wo: emitters emit from the front
// side of their winding only.
RAYCOH_HD RAYCOH_INLINE Vec3 emission_seen(const ShadingPoint& sp, Vec3 le) {
  return sp.cls == MaterialClass::Emissive && sp.front_face ? le : Vec3(0.f);
}

// ---- next-event estimation (shading/next_event.cpp) ----

// Shadow rays stop this fraction short of the sampled light point, so that the light itself is not an occluder.
constexpr float kShadowEpsilon = 1e-4f;

// A shadow ray with the light it delivers if it arrives (found == false: none).
struct ShadowSample {
  bool found = false;
  Ray ray;
  Vec3 beta{0.f, 0.f, 0.f};
};

// The shadow ray towards a light direction dir (tmax, radiance / pdf, light pdf: infinite for delta lights) from
// vertex sp with BSDF m and throughput beta, MIS-weighted against BSDF sampling; none when the BSDF gives nothing.
RAYCOH_HD RAYCOH_INLINE ShadowSample shadow_ray(const ShadingPoint& sp, const BsdfParams& m, Vec3 beta, Vec3 dir,
                                                float tmax, Vec3 radiance_over_pdf, float light_pdf) {
  ShadowSample s;
  const DirectionSample e = evaluate_direction(m, sp.ns, sp.ng, sp.wo, dir);
  if (!(max_component(e.weight) > 0.f) || !(e.pdf > 0.f)) return s;
  const Vec3 f_cos = e.weight * e.pdf;
  s.beta = beta * f_cos * radiance_over_pdf * power_heuristic(light_pdf, e.pdf);
  s.ray.org = offset_ray_origin(sp.position, dot(dir, sp.ng) >= 0.f ? sp.ng : -sp.ng);
  s.ray.dir = dir;
  s.ray.tmin = 0.f;
  s.ray.tmax = tmax;
  s.found = true;
  return s;
}

// The two shadow rays of a non-delta vertex of bounce b at pixel p: out[0] towards an emitter, out[1] towards the
// sun (sun.on) or a punctual light (a scene has one or the other).
RAYCOH_HD RAYCOH_INLINE void next_event_rays(const LightsView& lights, const Environment& env, const SunSampler& sun,
                                             const ShadingPoint& sp, const BsdfParams& m, Vec3 beta, uint32_t seed,
                                             uint32_t frame, uint32_t p, int bounce, ShadowSample out[2]) {
  out[0] = ShadowSample{};
  out[1] = ShadowSample{};
  if (is_delta(sp.cls)) return;
  if (lights.count > 0) {
    const EmitterSample e =
        emitter_sample(lights, sp, bounce_rand(seed, frame, p, bounce, kEmitterPick),
                       bounce_rand(seed, frame, p, bounce, kEmitterU), bounce_rand(seed, frame, p, bounce, kEmitterV));
    if (e.found)
      out[0] = shadow_ray(sp, m, beta, e.dir, e.dist * (1.f - kShadowEpsilon), e.emission * (1.f / e.pdf), e.pdf);
  }
  if (sun.on) {
    const Vec3 dir = sun.sample(bounce_rand(seed, frame, p, bounce, kSunU), bounce_rand(seed, frame, p, bounce, kSunV));
    out[1] = shadow_ray(sp, m, beta, dir, __builtin_huge_valf(), env.sun_radiance * (1.f / sun.pdf), sun.pdf);
  } else if (lights.light_count > 0) {
    const PunctualSample l = punctual_sample(lights, sp, bounce_rand(seed, frame, p, bounce, kLightPick));
    if (l.found)
      out[1] =
          shadow_ray(sp, m, beta, l.dir, l.dist * (1.f - kShadowEpsilon), l.irradiance_over_pmf, __builtin_huge_valf());
  }
}

// Fraction of light a thin pane lets through straight, seen along wo from the side of ns (core/bsdf.h's
// thin-walled dielectric: transmitted with probability 1 - F and weight base colour).
RAYCOH_HD RAYCOH_INLINE Vec3 pane_transmittance(const BsdfParams& m, const ShadingPoint& sp) {
  const float cos_i = std_clamp(dot(sp.wo, sp.ns), 0.f, 1.f);
  return m.base_color * (1.f - fresnel_dielectric(cos_i, m.ior));
}

// A shadow ray stopped at distance t by surface sp (BSDF m): through a thin pane it goes on behind it, attenuated,
// with one pane fewer left. Returns whether it goes on (ray, beta and panes_left then updated).
RAYCOH_HD RAYCOH_INLINE bool pass_pane(const ShadingPoint& sp, const BsdfParams& m, float t, Ray& ray, Vec3& beta,
                                       uint8_t& panes_left) {
  if (!is_thin_pane(m) || panes_left == 0) return false;
  ray.tmax -= t;
  if (!(ray.tmax > 0.f)) return false;
  ray.org = offset_ray_origin(sp.position, -sp.ng);
  beta = beta * pane_transmittance(m, sp);
  --panes_left;
  return max_component(beta) > 0.f;
}

// ---- bounce sampling (shading/bounce_sampling.cpp) ----

// The MIS state of a first-bounce ray leaving camera hit sp (BSDF m) in direction dir with the generator's pdf
// and the class it sampled: a straight pass through a thin pane keeps the camera's state (delta).
RAYCOH_HD RAYCOH_INLINE MisState first_bounce_mis(const ShadingPoint& sp, const BsdfParams& m, Vec3 dir, float pdf,
                                                  MaterialClass sampled) {
  const bool pass = is_thin_pane(m) && dot(dir, sp.ng) < 0.f;
  return pass ? MisState{} : MisState{pdf, static_cast<uint8_t>(is_delta(sampled)), 0.f};
}

// A BSDF-sampled ray leaving a vertex (found == false: absorbed, or ended by Russian roulette).
struct BounceSample {
  bool found = false;
  Ray ray;
  Vec3 beta{0.f, 0.f, 0.f};
  MisState mis;
};

// The direction leaving vertex sp (BSDF m, throughput beta, arriving MIS state mis) of bounce b at pixel p; with
// roulette, the path survives with probability min(1, max component of its throughput) and is divided by it.
RAYCOH_HD RAYCOH_INLINE BounceSample sample_bounce(const ShadingPoint& sp, const BsdfParams& m, Vec3 beta,
                                                   const MisState& mis, uint32_t seed, uint32_t frame, uint32_t p,
                                                   int bounce, bool roulette) {
  BounceSample out;
  const DirectionSample s =
      sample_direction(m, sp.ns, sp.ng, sp.wo, sp.front_face, bounce_rand(seed, frame, p, bounce, kDirU),
                       bounce_rand(seed, frame, p, bounce, kDirV), bounce_rand(seed, frame, p, bounce, kLobe));
  Vec3 b = beta * s.weight;
  if (!(max_component(b) > 0.f)) return out;
  if (roulette) {
    const float survive = std_min(1.f, max_component(b));
    if (bounce_rand(seed, frame, p, bounce, kRoulette) >= survive) return out;
    b = b * (1.f / survive);
  }
  out.ray.org = offset_ray_origin(sp.position, dot(s.dir, sp.ng) >= 0.f ? sp.ng : -sp.ng);
  out.ray.dir = s.dir;
  out.ray.tmin = 0.f;
  out.ray.tmax = __builtin_huge_valf();
  out.beta = b;
  const bool pass = (s.flags & kSampleTransmitted) != 0 && is_thin_pane(m);
  out.mis = pass ? mis : MisState{s.pdf, static_cast<uint8_t>(is_delta(sp.cls)), 0.f};
  out.found = true;
  return out;
}

// ---- hit gathering (shading/hit_gathering.cpp) ----

// Sky and sun seen by a ray that left the scene in direction dir.
RAYCOH_HD RAYCOH_INLINE Vec3 missed_light(const Environment& env, Vec3 dir, const MisState& mis) {
  Vec3 light = sky_radiance(env, dir);
  if (in_sun_cone(env, dir))
    light += env.sun_radiance * (mis.delta ? 1.f : power_heuristic(mis.pdf, sun_cone_pdf(env)));
  return light;
}

// Emission le of surface sp seen at distance t along a ray with MIS state mis, weighted against next-event
// estimation's pdf of the same point.
RAYCOH_HD RAYCOH_INLINE Vec3 emitted_light(const LightsView& lights, const ShadingPoint& sp, Vec3 le_entry,
                                           const MisState& mis, float t) {
  const Vec3 le = emission_seen(sp, le_entry);
  if (!(max_component(le) > 0.f)) return Vec3(0.f);
  float w = 1.f;
  if (!mis.delta && lights.count > 0 && lights.pmf_by_prim[sp.prim] > 0.f) {
    const float cos_y = dot(sp.ng, sp.wo), dist = mis.dist + t;
    w = power_heuristic(mis.pdf, emitter_pdf(lights, sp.prim, dist, cos_y));
  }
  return le * w;
}

}  // namespace raycoh
