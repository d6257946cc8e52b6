// Power-proportional choice of an emissive triangle and a uniform point on it (emitters.h).
#include "shading/emitters.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/sampling.h"

namespace raycoh {

namespace {

float luminance(Vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

// The cdf of power (all entries positive) and the exact probability that the first cdf entry above u is entry i
// for u on rng_float's grid of 2^-24 steps.
void exact_pick_probabilities(const std::vector<double>& power, std::vector<float>& cdf, std::vector<float>& pmf) {
  const double total = std::accumulate(power.begin(), power.end(), 0.0);
  constexpr double kGrid = 16777216.0;  // rng_float's values are k / 2^24
  double run = 0, below = 0;            // below: grid points under the previous cdf entry
  cdf.resize(power.size());
  pmf.resize(power.size());
  for (size_t i = 0; i < power.size(); ++i) {
    run += power[i];
    cdf[i] = i + 1 == power.size() ? 1.f : static_cast<float>(run / total);
    const double upto = std::ceil(static_cast<double>(cdf[i]) * kGrid);
    pmf[i] = static_cast<float>((upto - below) / kGrid);
    below = upto;
  }
}

size_t first_above(const std::vector<float>& cdf, float u) {
  const size_t i = static_cast<size_t>(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin());
  return std::min(i, cdf.size() - 1);
}

double light_power(const PunctualLight& l, double scene_radius) {
  constexpr double kPi = 3.14159265358979323846;
  const double i = luminance(l.intensity);
  switch (l.type) {
    case LightType::Point:
      return 4.0 * kPi * i;
    case LightType::Spot:
      return 2.0 * kPi * i * (1.0 - 0.5 * (static_cast<double>(l.cos_inner) + l.cos_outer));
    case LightType::Directional:
      return kPi * scene_radius * scene_radius * i;
  }
  return 0.0;
}

}  // namespace

Vec3 punctual_irradiance(const PunctualLight& l, Vec3 dir, float d) {
  if (l.type == LightType::Directional) return l.intensity;
  float w = 1.f / (d * d);
  if (l.range > 0.f) {
    const float x = d / l.range, x2 = x * x;
    w *= std::clamp(1.f - x2 * x2, 0.f, 1.f);
  }
  if (l.type == LightType::Spot) {
    const float t =
        std::clamp((dot(l.direction, dir) - l.cos_outer) / std::max(1e-3f, l.cos_inner - l.cos_outer), 0.f, 1.f);
    w *= t * t;
  }
  return l.intensity * w;
}

PunctualLights::PunctualLights(const Scene& scene) {
  if (scene.lights.empty()) return;
  const double radius = 0.5 * static_cast<double>(length(scene.bounds.extent()));
  std::vector<double> power;
  for (const PunctualLight& l : scene.lights) {
    const double p = light_power(l, radius);
    // A light with no power is never picked (finalize_scene keeps only lights with an intensity).
    power.push_back(p > 0.0 && std::isfinite(p) ? p : 0.0);
  }
  if (!(std::accumulate(power.begin(), power.end(), 0.0) > 0.0)) return;
  exact_pick_probabilities(power, cdf, pmf);
}

PunctualSample PunctualLights::sample(const Scene& scene, const ShadingPoint& sp, float u_pick) const {
  PunctualSample s;
  const size_t i = first_above(cdf, u_pick);
  const PunctualLight& l = scene.lights[i];
  if (!(pmf[i] > 0.f)) return s;
  if (l.type == LightType::Directional) {
    s.dir = -l.direction;
    s.dist = __builtin_huge_valf();
    s.irradiance_over_pmf = l.intensity * (1.f / pmf[i]);
    s.found = true;
    return s;
  }
  const Vec3 origin = offset_ray_origin(sp.position, dot(l.position - sp.position, sp.ng) >= 0.f ? sp.ng : -sp.ng);
  const Vec3 d = l.position - origin;
  const float dist2 = dot(d, d);
  if (!(dist2 > 0.f)) return s;
  s.dist = std::sqrt(dist2);
  s.dir = d * (1.f / s.dist);
  const Vec3 e = punctual_irradiance(l, -s.dir, s.dist);
  if (!(max_component(e) > 0.f)) return s;
  s.irradiance_over_pmf = e * (1.f / pmf[i]);
  s.found = true;
  return s;
}

EmitterDistribution::EmitterDistribution(const Scene& scene) : punctual(scene) {
  std::vector<double> power, area;
  for (uint32_t t : scene.emissive_tris) {
    const uint32_t* idx = &scene.indices[3 * static_cast<size_t>(t)];
    const Vec3 e1 = scene.positions[idx[1]] - scene.positions[idx[0]];
    const Vec3 e2 = scene.positions[idx[2]] - scene.positions[idx[0]];
    const double a = 0.5 * static_cast<double>(length(cross(e1, e2)));
    // An emissive texture's triangle: the mean of its emissive texels (the loader's, at its texel density).
    const Vec3 e = scene.textures.emission_textured(t) ? scene.textures.tri_emission[t]
                                                       : scene.materials[scene.tri_material[t]].emission;
    const double p = a * luminance(e);
    if (!(p > 0.0) || !std::isfinite(p)) continue;
    tris.push_back(t);
    power.push_back(p);
    area.push_back(a);
  }
  if (tris.empty()) return;
  pmf_by_prim.assign(scene.triangle_count(), 0.f);
  area_by_prim.assign(scene.triangle_count(), 0.f);
  std::vector<float> pmf;
  exact_pick_probabilities(power, cdf, pmf);
  for (size_t i = 0; i < tris.size(); ++i) {
    pmf_by_prim[tris[i]] = pmf[i];
    area_by_prim[tris[i]] = static_cast<float>(area[i]);
  }
}

size_t EmitterDistribution::pick(float u) const { return first_above(cdf, u); }

EmitterSample EmitterDistribution::sample(const Scene& scene, const ShadingPoint& sp, float u_pick, float u,
                                          float v) const {
  EmitterSample s;
  const uint32_t t = tris[pick(u_pick)];
  const uint32_t* idx = &scene.indices[3 * static_cast<size_t>(t)];
  const Vec3 v0 = scene.positions[idx[0]], v1 = scene.positions[idx[1]], v2 = scene.positions[idx[2]];
  const float su = std::sqrt(u);
  const float b1 = 1.f - su, b2 = v * su;
  const Vec3 y = v0 * (1.f - b1 - b2) + v1 * b1 + v2 * b2;
  const Vec3 origin = offset_ray_origin(sp.position, dot(y - sp.position, sp.ng) >= 0.f ? sp.ng : -sp.ng);
  const Vec3 d = y - origin;
  const float dist2 = dot(d, d);
  const float area = area_by_prim[t];
  if (!(dist2 > 0.f && area > 0.f)) return s;
  s.dist = std::sqrt(dist2);
  s.dir = d * (1.f / s.dist);
  const float cos_y = -dot(normalize(cross(v1 - v0, v2 - v0)), s.dir);
  if (!(cos_y > 0.f)) return s;
  // The squared distance of the sample itself: pdf() squares a traced distance instead, which rounds differently.
  s.pdf = pmf_by_prim[t] / area * dist2 / cos_y;
  // What a ray hitting this point finds (make_gbuffer): the texel's emission on a textured triangle.
  if (scene.textures.textured(t)) {
    const SurfaceTexturesView view = scene.textures.view();
    float uv[2][2];
    hit_uv(view, t, b1, b2, uv);
    s.emission = emission_of(view, view.materials[view.tri_material[t]], uv);
  } else {
    s.emission = scene.materials[scene.tri_material[t]].emission;
  }
  s.found = true;
  return s;
}

}  // namespace raycoh
