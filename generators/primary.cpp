// Primary rays (pinhole camera) and G-buffer construction: interpolated position, geometric and shading
// normals oriented towards the viewer, material class. Parallel over pixels with oneTBB.
#include "generators/primary.h"

#include <tbb/parallel_for.h>

#include <cmath>

#include "core/sampling.h"
#include "core/surface_textures.h"
#include "generators/generator.h"
#include "generators/primary_ray.h"

namespace raycoh {

void RayBatch::resize(size_t n, bool with_groups) {
#define RAYCOH_RESIZE(name, T, grouped) name.resize(grouped && !with_groups ? 0 : n);
  RAYCOH_BATCH_COLUMNS(RAYCOH_RESIZE)
#undef RAYCOH_RESIZE
}

const char* to_string(GroupType t) {
  switch (t) {
    case GroupType::Diffuse:
      return "diffuse";
    case GroupType::Glossy:
      return "glossy";
    case GroupType::Hybrid:
      return "hybrid";
    case GroupType::WorldShared:
      return "world";
    default:
      return "independent";
  }
}

PixelRays make_primary_rays(const Camera& camera, int width, int height, const std::vector<uint32_t>& order,
                            uint32_t seed, uint32_t frame, bool jitter) {
  PixelRays out;
  out.width = width;
  out.height = height;
  out.frame = frame;
  out.rays.resize(order.size());
  out.pixel = order;
  const PinholeCamera pinhole = make_pinhole_camera(camera, width, height);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, order.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) {
      out.rays[i] = primary_ray(pinhole, order[i], seed, frame, jitter);
    }
  });
  return out;
}

GBuffer make_gbuffer(const Scene& scene, const PixelRays& primary, const std::vector<Hit>& hits) {
  GBuffer g;
  g.width = primary.width;
  g.height = primary.height;
  g.frame = primary.frame;
  g.points.assign(static_cast<size_t>(g.width) * g.height, ShadingPoint{});
  const bool textured = !scene.textures.empty();
  const SurfaceTexturesView tex = scene.textures.view();
  // The material table: the scene's materials, then (textured scenes) one entry per point slot.
  auto table = std::make_shared<HitMaterials>();
  const size_t nm = scene.materials.size();
  table->scene_count = nm;
  table->bsdf.reserve(nm + (textured ? g.points.size() : 0));
  for (const Material& m : scene.materials) {
    table->bsdf.push_back(bsdf_params(m));
    table->emission.push_back(m.emission);
  }
  if (textured) {
    table->bsdf.resize(nm + g.points.size());
    table->emission.resize(nm + g.points.size());
  }
  tbb::parallel_for(tbb::blocked_range<size_t>(0, primary.rays.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) {
      const Hit& h = hits[i];
      if (!h.valid()) continue;
      const Ray& ray = primary.rays[i];
      const uint32_t* idx = &scene.indices[3 * static_cast<size_t>(h.prim)];
      const Vec3 v0 = scene.positions[idx[0]], v1 = scene.positions[idx[1]], v2 = scene.positions[idx[2]];
      const float w0 = 1.f - h.u - h.v;
      ShadingPoint& sp = g.points[primary.pixel[i]];
      sp.prim = h.prim;
      sp.material = scene.tri_material[h.prim];
      sp.cls = scene.materials[sp.material].cls;
      sp.position = v0 * w0 + v1 * h.u + v2 * h.v;
      sp.wo = -ray.dir;
      Vec3 ng = cross(v1 - v0, v2 - v0);
      ng = dot(ng, ng) > 0.f ? normalize(ng) : sp.wo;
      sp.front_face = dot(ng, sp.wo) >= 0.f;
      if (!sp.front_face) ng = -ng;
      Vec3 ns = scene.normals[idx[0]] * w0 + scene.normals[idx[1]] * h.u + scene.normals[idx[2]] * h.v;
      ns = dot(ns, ns) > 0.f ? normalize(ns) : ng;
      if (!is_finite(ns)) ns = ng;
      if (textured && tex.tri_material[h.prim] != kNoTexture) {
        const SurfaceSample s = surface_at(tex, h.prim, h.u, h.v);
        const size_t slot = nm + primary.pixel[i];
        table->bsdf[slot] = s.bsdf;
        table->emission[slot] = s.emission;
        sp.material = static_cast<uint32_t>(slot);
        sp.cls = s.bsdf.cls;
        // A normal-mapped normal that crosses the geometric surface (or turns away from the interpolated one) is
        // not used: the interpolated normal stays.
        if (s.has_normal) {
          const Vec3 mapped = apply_normal_map(tex, h.prim, ns, s.normal_ts);
          if (dot(mapped, ns) > 0.f && (dot(mapped, ng) > 0.f) == (dot(ns, ng) > 0.f)) ns = mapped;
        }
      }
      if (dot(ns, ng) < 0.f) ns = -ns;
      sp.ng = ng;
      sp.ns = ns;
    }
  });
  for (const ShadingPoint& sp : g.points) g.hits += sp.valid();
  g.materials = std::move(table);
  return g;
}

}  // namespace raycoh
