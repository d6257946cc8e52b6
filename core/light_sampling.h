// Lights of next-event estimation, written once for host and device: emissive triangles chosen with probability
// proportional to their power and a uniform point on the chosen one, and punctual lights (glTF
// KHR_lights_punctual) chosen likewise. The method and its sources are shading/emitters.h's doc block; that file
// builds the distributions on the host (EmitterDistribution, PunctualLights) and samples them through these
// functions, as the device path tracer does on the device (cuda/device_shading.cu) over the same arrays.
#pragma once

#include "core/environment_light.h"
#include "core/hit_surface.h"
#include "core/platform.h"
#include "core/ray_batch.h"
#include "core/sampling.h"
#include "core/surface_textures.h"

namespace raycoh {

enum class LightType : uint8_t { Point = 0, Spot = 1, Directional = 2 };

// What sampling reads of a punctual light (scenes/scene.h PunctualLight without its name).
struct PunctualLightView {
  LightType type = LightType::Point;
  Vec3 position{0.f, 0.f, 0.f};
  Vec3 direction{0.f, 0.f, -1.f};  // the way the light travels
  Vec3 intensity{1.f, 1.f, 1.f};
  float range = 0.f;
  float cos_inner = 1.f, cos_outer = 0.f;
};

// A point on an emitter seen from a shading point.
struct EmitterSample {
  bool found = false;  // false: no light from this sample (degenerate, or the point sees the emitter's back)
  Vec3 dir;            // unit, from the offset ray origin towards the point
  float dist = 0.f;    // from the offset ray origin to the point
  float pdf = 0.f;     // solid angle, triangle choice included
  Vec3 emission;
};

// A light direction from a shading point with what it delivers, divided by the probability of the choice.
struct PunctualSample {
  bool found = false;        // false: the point is outside the light's cone or range
  Vec3 dir;                  // unit, from the offset ray origin towards the light
  float dist = 0.f;          // to the light; infinite for directional lights
  Vec3 irradiance_over_pmf;  // irradiance on a surface facing the light, over the choice's probability
};

// The light distributions of one scene as plain arrays (shading/emitters.h EmitterDistribution::view).
struct LightsView {
  MeshView mesh{};                          // positions, indices, tri_material, textures
  const Vec3* material_emission = nullptr;  // per scene material
  // Emissive triangles: tris[count], cdf[count] (inclusive, last = 1); per scene triangle the exact probability
  // of picking it and its area (0 for non-emitters). count == 0: no emitters (the per-triangle arrays are null).
  const uint32_t* tris = nullptr;
  const float* cdf = nullptr;
  uint32_t count = 0;
  const float* pmf_by_prim = nullptr;
  const float* area_by_prim = nullptr;
  // Punctual lights: light_cdf, light_pmf, lights [light_count]; light_count == 0: none.
  const float* light_cdf = nullptr;
  const float* light_pmf = nullptr;
  const PunctualLightView* lights = nullptr;
  uint32_t light_count = 0;
};

// std::upper_bound over cdf[0, n) (the first entry above u), clamped to the last entry; n > 0.
RAYCOH_HD RAYCOH_INLINE uint32_t first_above(const float* cdf, uint32_t n, float u) {
  uint32_t lo = 0, len = n;
  while (len > 0) {
    const uint32_t half = len / 2;
    if (!(u < cdf[lo + half])) {
      lo += half + 1;
      len -= half + 1;
    } else {
      len = half;
    }
  }
  return lo < n - 1 ? lo : n - 1;
}

// Solid-angle pdf with which emitter_sample finds emitter prim at distance dist and cosine cos_y on its side.
RAYCOH_HD RAYCOH_INLINE float emitter_pdf(const LightsView& l, uint32_t prim, float dist, float cos_y) {
  return l.pmf_by_prim[prim] / l.area_by_prim[prim] * dist * dist / cos_y;
}

// A point on an emitter for the uniform numbers u_pick (which triangle), u and v (where on it), seen from sp
// (Shirley's square-root map, as pbrt-v4's SampleUniformTriangle). l.count > 0.
RAYCOH_HD RAYCOH_INLINE EmitterSample emitter_sample(const LightsView& l, const ShadingPoint& sp, float u_pick, float u,
                                                     float v) {
  EmitterSample s;
  const uint32_t t = l.tris[first_above(l.cdf, l.count, u_pick)];
  const uint32_t* idx = l.mesh.indices + 3 * static_cast<uint64_t>(t);
  const Vec3 v0 = l.mesh.positions[idx[0]], v1 = l.mesh.positions[idx[1]], v2 = l.mesh.positions[idx[2]];
  const float su = sqrtf(u);
  const float b1 = 1.f - su, b2 = v * su;
  const Vec3 y = v0 * (1.f - b1 - b2) + v1 * b1 + v2 * b2;
  const Vec3 origin = offset_ray_origin(sp.position, dot(y - sp.position, sp.ng) >= 0.f ? sp.ng : -sp.ng);
  const Vec3 d = y - origin;
  const float dist2 = dot(d, d);
  const float area = l.area_by_prim[t];
  if (!(dist2 > 0.f && area > 0.f)) return s;
  s.dist = sqrtf(dist2);
  s.dir = d * (1.f / s.dist);
  const float cos_y = -dot(normalize(cross(v1 - v0, v2 - v0)), s.dir);
  if (!(cos_y > 0.f)) return s;
  // The squared distance of the sample itself: emitter_pdf squares a traced distance instead, which rounds
  // differently.
  s.pdf = l.pmf_by_prim[t] / area * dist2 / cos_y;
  // What a ray hitting this point finds (hit_surface): the texel's emission on a textured triangle.
  if (textured_triangle(l.mesh, t)) {
    const SurfaceTexturesView& view = l.mesh.textures;
    float uv[2][2];
    hit_uv(view, t, b1, b2, uv);
    s.emission = emission_of(view, view.materials[view.tri_material[t]], uv);
  } else {
    s.emission = l.material_emission[l.mesh.tri_material[t]];
  }
  s.found = true;
  return s;
}

// What light lt delivers at distance d along unit direction dir (from the light towards the point): I / d^2 with
// the spot cone and range windows for point and spot lights (d unused for directional lights: E).
RAYCOH_HD RAYCOH_INLINE Vec3 punctual_irradiance(const PunctualLightView& lt, Vec3 dir, float d) {
  if (lt.type == LightType::Directional) return lt.intensity;
  float w = 1.f / (d * d);
  if (lt.range > 0.f) {
    const float x = d / lt.range, x2 = x * x;
    w *= std_clamp(1.f - x2 * x2, 0.f, 1.f);
  }
  if (lt.type == LightType::Spot) {
    const float t =
        std_clamp((dot(lt.direction, dir) - lt.cos_outer) / std_max(1e-3f, lt.cos_inner - lt.cos_outer), 0.f, 1.f);
    w *= t * t;
  }
  return lt.intensity * w;
}

// The punctual light for the uniform number u_pick, seen from sp. l.light_count > 0.
RAYCOH_HD RAYCOH_INLINE PunctualSample punctual_sample(const LightsView& l, const ShadingPoint& sp, float u_pick) {
  PunctualSample s;
  const uint32_t i = first_above(l.light_cdf, l.light_count, u_pick);
  const PunctualLightView& lt = l.lights[i];
  if (!(l.light_pmf[i] > 0.f)) return s;
  if (lt.type == LightType::Directional) {
    s.dir = -lt.direction;
    s.dist = __builtin_huge_valf();
    s.irradiance_over_pmf = lt.intensity * (1.f / l.light_pmf[i]);
    s.found = true;
    return s;
  }
  const Vec3 origin = offset_ray_origin(sp.position, dot(lt.position - sp.position, sp.ng) >= 0.f ? sp.ng : -sp.ng);
  const Vec3 d = lt.position - origin;
  const float dist2 = dot(d, d);
  if (!(dist2 > 0.f)) return s;
  s.dist = sqrtf(dist2);
  s.dir = d * (1.f / s.dist);
  const Vec3 e = punctual_irradiance(lt, -s.dir, s.dist);
  if (!(max_component(e) > 0.f)) return s;
  s.irradiance_over_pmf = e * (1.f / l.light_pmf[i]);
  s.found = true;
  return s;
}

}  // namespace raycoh
