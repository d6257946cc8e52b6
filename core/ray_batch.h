// The G-buffer of first hits and the secondary ray batch made from it (host side).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/ray.h"
#include "scenes/scene.h"

namespace raycoh {

// One first hit. Normals face the side the camera ray came from (all shared-scene materials are double-sided):
// ng is the geometric normal, ns the interpolated shading normal (tilted by a normal map where the material has
// one) flipped into ng's hemisphere. bsdf and emission are the material at this very point: the triangle's
// material, or for a textured glTF material the texels at the hit (core/surface_textures.h); every stage, host
// and device, reads them from here (bsdf.cls is the point's class).
struct ShadingPoint {
  Vec3 position;
  Vec3 ng;
  Vec3 ns;
  Vec3 wo;  // unit, towards the camera
  uint32_t prim = kNoHit;
  uint32_t material = 0;  // the triangle's entry in Scene::materials (for a textured one, its 16-texel mean)
  BsdfParams bsdf;
  Vec3 emission{0.f, 0.f, 0.f};  // radiance the front face emits
  bool front_face = true;        // the camera ray hit the side the triangle's winding faces
  bool valid() const { return prim != kNoHit; }
};

// Per pixel (index y * width + x).
struct GBuffer {
  int width = 0, height = 0;
  uint32_t frame = 0;
  std::vector<ShadingPoint> points;
  size_t hits = 0;
};

// How a group of pixels shares directions (the paper, section 3.2): all-diffuse groups share one tangent-space
// direction; all-glossy groups sample their own; hybrid groups give diffuse members the glossy members' mean
// tangent-space direction. Transmissive members always sample their own (the paper does not handle them); a
// group whose hit members are all transmissive is "independent". Direct reuse shares one world direction.
enum class GroupType : uint8_t { Independent = 0, Diffuse = 1, Glossy = 2, Hybrid = 3, WorldShared = 4 };
const char* to_string(GroupType t);

// Structure-of-arrays batch; element i of every array belongs to ray i. The order of the batch is part of the
// method (DESIGN.md section 1): warps are 32 consecutive rays.
struct RayBatch {
  int width = 0, height = 0;
  uint32_t frame = 0;
  std::vector<Ray> rays;
  std::vector<uint32_t> pixel;          // y * width + x of the shading point the ray leaves
  std::vector<float> pdf;               // solid-angle pdf of the direction (discrete probability for delta lobes)
  std::vector<Vec3> weight;             // BSDF x cos / pdf; zero for directions that were rejected
  std::vector<Vec3> normal;             // shading normal at the origin
  std::vector<MaterialClass> material;  // class of the material at the origin
  // Filled by grouping generators only (empty otherwise): tile index (row-major over the image's tiles), group
  // id unique in the frame (tile * groups_per_tile + group in tile) and the group's type.
  std::vector<uint32_t> tile;
  std::vector<uint32_t> group;
  std::vector<GroupType> group_type;

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
