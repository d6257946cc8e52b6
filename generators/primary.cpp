// Primary rays (pinhole camera) and G-buffer construction: interpolated position, geometric and shading
// normals oriented towards the viewer, material class. Parallel over pixels with oneTBB.
#include "generators/primary.h"

#include <tbb/parallel_for.h>

#include <cmath>

#include "core/hit_surface.h"
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
  std::vector<MaterialClass> classes;
  for (const Material& m : scene.materials) classes.push_back(m.cls);
  MeshView mesh;
  mesh.positions = scene.positions.data();
  mesh.normals = scene.normals.data();
  mesh.indices = scene.indices.data();
  mesh.tri_material = scene.tri_material.data();
  mesh.material_cls = classes.data();
  mesh.textures = scene.textures.view();
  mesh.textured = textured;
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
      // core/hit_surface.h: the same function makes the device path tracer's vertices.
      const HitSurface surface = hit_surface(mesh, primary.rays[i], h);
      ShadingPoint& sp = g.points[primary.pixel[i]];
      sp = surface.point;
      if (surface.textured) {
        const size_t slot = nm + primary.pixel[i];
        table->bsdf[slot] = surface.bsdf;
        table->emission[slot] = surface.emission;
        sp.material = static_cast<uint32_t>(slot);
      }
    }
  });
  for (const ShadingPoint& sp : g.points) g.hits += sp.valid();
  g.materials = std::move(table);
  return g;
}

}  // namespace raycoh
