// The shading point of a closest hit, written once for host and device: make_gbuffer (generators/primary.h) builds
// every G-buffer and every path vertex of the CPU path tracer with it, and the device path tracer
// (cuda/device_shading.cu) its later vertices. Interpolated position, geometric normal towards the incoming ray
// (front_face: the ray hit the side the winding faces), interpolated shading normal (tilted by a normal texel
// where the material has one, unless that crosses the geometric surface or turns away from the interpolated
// normal) flipped into the geometric normal's hemisphere, the material and its class; on a textured triangle the
// BSDF and emission of the texel hit (core/surface_textures.h).
#pragma once

#include "core/platform.h"
#include "core/ray.h"
#include "core/ray_batch.h"
#include "core/surface_textures.h"
#include "core/vec.h"

namespace raycoh {

// A scene's triangles and materials as plain arrays, valid on whichever side they live.
struct MeshView {
  const Vec3* positions = nullptr;
  const Vec3* normals = nullptr;
  const uint32_t* indices = nullptr;            // 3 per triangle
  const uint32_t* tri_material = nullptr;       // per triangle: scene material
  const MaterialClass* material_cls = nullptr;  // per scene material
  SurfaceTexturesView textures{};
  bool textured = false;  // the scene has surface textures (textures' arrays are valid)
};

// A hit's shading point (material: the scene material) and, where textured, the texel's BSDF and emission
// (point.cls is then the texel's class).
struct HitSurface {
  ShadingPoint point;
  bool textured = false;
  BsdfParams bsdf;
  Vec3 emission{0.f, 0.f, 0.f};
};

RAYCOH_HD RAYCOH_INLINE bool textured_triangle(const MeshView& m, uint32_t prim) {
  return m.textured && m.textures.tri_material[prim] != kNoTexture;
}

// The surface at valid hit h of ray.
RAYCOH_HD RAYCOH_INLINE HitSurface hit_surface(const MeshView& m, const Ray& ray, const Hit& h) {
  HitSurface out;
  ShadingPoint& sp = out.point;
  const uint32_t* idx = m.indices + 3 * static_cast<uint64_t>(h.prim);
  const Vec3 v0 = m.positions[idx[0]], v1 = m.positions[idx[1]], v2 = m.positions[idx[2]];
  const float w0 = 1.f - h.u - h.v;
  sp.prim = h.prim;
  sp.material = m.tri_material[h.prim];
  sp.cls = m.material_cls[sp.material];
  sp.position = v0 * w0 + v1 * h.u + v2 * h.v;
  sp.wo = -ray.dir;
  Vec3 ng = cross(v1 - v0, v2 - v0);
  ng = dot(ng, ng) > 0.f ? normalize(ng) : sp.wo;
  sp.front_face = dot(ng, sp.wo) >= 0.f;
  if (!sp.front_face) ng = -ng;
  Vec3 ns = m.normals[idx[0]] * w0 + m.normals[idx[1]] * h.u + m.normals[idx[2]] * h.v;
  ns = dot(ns, ns) > 0.f ? normalize(ns) : ng;
  if (!is_finite(ns)) ns = ng;
  if (textured_triangle(m, h.prim)) {
    const SurfaceSample s = surface_at(m.textures, h.prim, h.u, h.v);
    out.textured = true;
    out.bsdf = s.bsdf;
    out.emission = s.emission;
    sp.cls = s.bsdf.cls;
    if (s.has_normal) {
      const Vec3 mapped = apply_normal_map(m.textures, h.prim, ns, s.normal_ts);
      if (dot(mapped, ns) > 0.f && (dot(mapped, ng) > 0.f) == (dot(ns, ng) > 0.f)) ns = mapped;
    }
  }
  if (dot(ns, ng) < 0.f) ns = -ns;
  sp.ng = ng;
  sp.ns = ns;
  return out;
}

}  // namespace raycoh
