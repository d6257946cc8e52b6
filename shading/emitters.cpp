// Power-proportional choice of an emissive triangle and a uniform point on it (emitters.h).
#include "shading/emitters.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.h"
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

PunctualLightView punctual_view(const PunctualLight& l) {
  PunctualLightView v;
  v.type = l.type;
  v.position = l.position;
  v.direction = l.direction;
  v.intensity = l.intensity;
  v.range = l.range;
  v.cos_inner = l.cos_inner;
  v.cos_outer = l.cos_outer;
  return v;
}

Vec3 punctual_irradiance(const PunctualLight& l, Vec3 dir, float d) {
  return punctual_irradiance(punctual_view(l), dir, d);
}

PunctualLights::PunctualLights(const Scene& scene) {
  if (scene.lights.empty()) return;
  for (const PunctualLight& l : scene.lights) lights.push_back(punctual_view(l));
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
  LightsView v;
  v.light_cdf = cdf.data();
  v.light_pmf = pmf.data();
  v.lights = lights.data();
  v.light_count = static_cast<uint32_t>(cdf.size());
  RAYCOH_CHECK(lights.size() == scene.lights.size(), "punctual lights of another scene");
  return punctual_sample(v, sp, u_pick);
}

EmitterDistribution::EmitterDistribution(const Scene& scene) : punctual(scene) {
  for (const Material& m : scene.materials) {
    material_emission.push_back(m.emission);
    material_cls.push_back(m.cls);
  }
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

size_t EmitterDistribution::pick(float u) const {
  return first_above(cdf.data(), static_cast<uint32_t>(cdf.size()), u);
}

LightsView EmitterDistribution::view(const Scene& scene) const {
  RAYCOH_CHECK(material_emission.size() == scene.materials.size(), "an emitter distribution of another scene");
  LightsView v;
  v.mesh.positions = scene.positions.data();
  v.mesh.normals = scene.normals.data();
  v.mesh.indices = scene.indices.data();
  v.mesh.tri_material = scene.tri_material.data();
  v.mesh.material_cls = material_cls.data();
  v.mesh.textures = scene.textures.view();
  v.mesh.textured = !scene.textures.empty();
  v.material_emission = material_emission.data();
  v.tris = tris.data();
  v.cdf = cdf.data();
  v.count = static_cast<uint32_t>(tris.size());
  v.pmf_by_prim = pmf_by_prim.data();
  v.area_by_prim = area_by_prim.data();
  v.light_cdf = punctual.cdf.data();
  v.light_pmf = punctual.pmf.data();
  v.lights = punctual.lights.data();
  v.light_count = static_cast<uint32_t>(punctual.cdf.size());
  return v;
}

EmitterSample EmitterDistribution::sample(const Scene& scene, const ShadingPoint& sp, float u_pick, float u,
                                          float v) const {
  return emitter_sample(view(scene), sp, u_pick, u, v);
}

}  // namespace raycoh
