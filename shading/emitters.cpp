// Power-proportional choice of an emissive triangle and a uniform point on it (emitters.h).
#include "shading/emitters.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/sampling.h"

namespace raycoh {

namespace {

float luminance(Vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

}  // namespace

EmitterDistribution::EmitterDistribution(const Scene& scene) {
  std::vector<double> power, area;
  for (uint32_t t : scene.emissive_tris) {
    const uint32_t* idx = &scene.indices[3 * static_cast<size_t>(t)];
    const Vec3 e1 = scene.positions[idx[1]] - scene.positions[idx[0]];
    const Vec3 e2 = scene.positions[idx[2]] - scene.positions[idx[0]];
    const double a = 0.5 * static_cast<double>(length(cross(e1, e2)));
    const double p = a * luminance(scene.materials[scene.tri_material[t]].emission);
    if (!(p > 0.0) || !std::isfinite(p)) continue;
    tris.push_back(t);
    power.push_back(p);
    area.push_back(a);
  }
  if (tris.empty()) return;
  pmf_by_prim.assign(scene.triangle_count(), 0.f);
  area_by_prim.assign(scene.triangle_count(), 0.f);
  const double total = std::accumulate(power.begin(), power.end(), 0.0);
  constexpr double kGrid = 16777216.0;  // rng_float's values are k / 2^24
  double run = 0, below = 0;            // below: grid points under the previous cdf entry
  cdf.resize(tris.size());
  for (size_t i = 0; i < tris.size(); ++i) {
    run += power[i];
    cdf[i] = i + 1 == tris.size() ? 1.f : static_cast<float>(run / total);
    const double upto = std::ceil(static_cast<double>(cdf[i]) * kGrid);
    pmf_by_prim[tris[i]] = static_cast<float>((upto - below) / kGrid);
    area_by_prim[tris[i]] = static_cast<float>(area[i]);
    below = upto;
  }
}

size_t EmitterDistribution::pick(float u) const {
  const size_t i = static_cast<size_t>(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin());
  return std::min(i, tris.size() - 1);
}

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
  s.emission = scene.materials[scene.tri_material[t]].emission;
  s.found = true;
  return s;
}

}  // namespace raycoh
