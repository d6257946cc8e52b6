// The G-buffer of first hits and the secondary ray batch made from it (host side).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/material.h"
#include "core/platform.h"
#include "core/ray.h"
#include "core/shading_point.h"

namespace raycoh {

// The materials a G-buffer's points index: the scene's materials (entries [0, scene_count)) and, in a scene with
// textures, one entry per point slot i at scene_count + i for the texel its hit found. Shared (read-only) by the
// G-buffer, the path vertices made from it and the generators.
struct HitMaterials {
  std::vector<BsdfParams> bsdf;
  std::vector<Vec3> emission;  // radiance an entry's front face emits
  size_t scene_count = 0;
  bool per_hit() const { return bsdf.size() > scene_count; }
};

// Per pixel (index y * width + x); a point is a ShadingPoint (core/shading_point.h: its 64-byte layout and the
// device's 16-byte reads).
struct GBuffer {
  int width = 0, height = 0;
  uint32_t frame = 0;
  std::vector<ShadingPoint> points;
  size_t hits = 0;
  // make_gbuffer's table; null in a G-buffer built by hand, whose points index the scene's materials (readers
  // then take Scene::materials: generators/generator.h material_table).
  std::shared_ptr<const HitMaterials> materials;
};

// How a group of pixels shares directions (the paper, section 3.2): all-diffuse groups share one tangent-space
// direction; all-glossy groups sample their own; hybrid groups give diffuse members the glossy members' mean
// tangent-space direction. Transmissive members always sample their own (the paper does not handle them); a
// group whose hit members are all transmissive is "independent". Direct reuse shares one world direction.
enum class GroupType : uint8_t { Independent = 0, Diffuse = 1, Glossy = 2, Hybrid = 3, WorldShared = 4 };
const char* to_string(GroupType t);
// A ray of a hybrid group whose own material class is diffuse: a pixel the hybrid rule gives another lobe's
// direction (generators/generator.h hybrid_diffuse_rays; the device's count, cuda/device_generators.h).
RAYCOH_HD RAYCOH_INLINE bool is_hybrid_diffuse(GroupType g, MaterialClass m) {
  return g == GroupType::Hybrid && m == MaterialClass::Diffuse;
}

// Structure-of-arrays batch; element i of every array belongs to ray i. The order of the batch is part of the
// method (docs/design.md section 1): warps are 32 consecutive rays.
// The ray batch's columns, declared once: X(name, element type, group column). A group column is filled by
// grouping generators only (empty otherwise). RayBatch holds a vector per column, BatchView (core/batch_view.h) a
// pointer; RayBatch::resize, permute_batch (encoders/permute.cpp), the device batches, their gather and download
// (cuda/device_batch.cuh) and the model's bytes per ray (simt/pipeline_model.cpp) expand this list, so a new ray
// attribute is one line here, and its value where core/batch_view.h's write_ray makes a ray.
//   rays        the ray
//   pixel       y * width + x of the shading point the ray leaves
//   pdf         solid-angle pdf of the direction (discrete probability for delta lobes)
//   weight      BSDF x cos / pdf; zero for directions that were rejected
//   normal      shading normal at the origin
//   material    class of the material at the origin
//   tile        tile index (row-major over the image's tiles)
//   group       group id unique in the frame (tile * groups_per_tile + group in tile)
//   group_type  the group's type
#define RAYCOH_BATCH_COLUMNS(X)     \
  X(rays, Ray, false)               \
  X(pixel, uint32_t, false)         \
  X(pdf, float, false)              \
  X(weight, Vec3, false)            \
  X(normal, Vec3, false)            \
  X(material, MaterialClass, false) \
  X(tile, uint32_t, true)           \
  X(group, uint32_t, true)          \
  X(group_type, GroupType, true)

struct RayBatch {
  int width = 0, height = 0;
  uint32_t frame = 0;
#define RAYCOH_BATCH_VECTOR(name, T, grouped) std::vector<T> name;
  RAYCOH_BATCH_COLUMNS(RAYCOH_BATCH_VECTOR)
#undef RAYCOH_BATCH_VECTOR

  size_t size() const { return rays.size(); }
  bool has_groups() const { return !group.empty(); }
  void resize(size_t n, bool with_groups = false);
};

// What a generator did in one frame, for the harness's reports.
struct GenerationStats {
  size_t rays = 0;
  size_t below_geometric = 0;  // directions on the wrong side of the geometric surface: kept, weight 0
  size_t below_shading = 0;    // glossy samples reflected below the shading hemisphere: kept, weight 0
  size_t non_finite = 0;       // NaN/Inf inputs or directions: the ray gets a finite stand-in and weight 0
  // Grouping generators: groups with at least one hit pixel, by type.
  size_t groups[5] = {0, 0, 0, 0, 0};  // indexed by GroupType
  size_t hybrid_mean_fallback = 0;     // hybrid groups whose mean glossy direction nearly cancelled
  size_t reused_rays = 0;              // rays whose direction came from another pixel
};

}  // namespace raycoh
