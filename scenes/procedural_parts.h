// The pieces the built-in procedural scenes share (scenes/procedural.cpp: cornell, voxels and the registry;
// scenes/stiff_cases.cpp: the stability catalogue). Internal to scenes/.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "core/params.h"
#include "scenes/scene.h"

namespace raycoh::procedural {

Material make_material(const char* name, Vec3 base, float roughness, float metallic = 0.f, Vec3 emission = {});

// Appends flat-shaded quads; each quad owns its four vertices so that normals stay per face.
struct QuadBuilder {
  Scene& scene;
  // 0: two triangles per quad. Otherwise five, watertight (no T-junction): a needle (A, E, D) whose short edge
  // DE is |CD| / aspect long, and a sliver (A, M, C) whose apex M lies |AC| / aspect off the diagonal AC.
  float aspect = 0.f;

  // Corners in order around the quad; the winding is fixed so that the geometric normal points along n.
  void quad(Vec3 p0, Vec3 p1, Vec3 p2, Vec3 p3, Vec3 n, uint32_t material) {
    if (dot(cross(p1 - p0, p2 - p0), n) < 0.f) std::swap(p1, p3);
    const uint32_t base = static_cast<uint32_t>(scene.positions.size());
    std::vector<Vec3> corners = {p0, p1, p2, p3};
    if (aspect > 0.f) {
      const Vec3 mid = (p0 + p2) * 0.5f, towards_b = p1 - mid;
      const float ac = length(p2 - p0);
      corners.push_back(p3 + (p2 - p3) * (1.f / aspect));                      // E, on CD next to D
      corners.push_back(mid + towards_b * (ac / aspect / length(towards_b)));  // M, inside ABC next to AC
    }
    for (const Vec3& p : corners) {
      scene.positions.push_back(p);
      scene.normals.push_back(n);
    }
    if (aspect > 0.f) {
      const uint32_t a = base, b = base + 1, c = base + 2, d = base + 3, e = base + 4, m = base + 5;
      scene.indices.insert(scene.indices.end(), {a, b, m, b, c, m, a, m, c, a, c, e, a, e, d});
      scene.tri_material.insert(scene.tri_material.end(), 5, material);
      return;
    }
    scene.indices.insert(scene.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    scene.tri_material.insert(scene.tri_material.end(), {material, material});
  }

  // A block standing on the floor with footprint corners f[0..3] (in order) and the given height: top and
  // four sides, no bottom.
  void block(const float (&f)[4][2], float height, uint32_t material) {
    Vec3 lo[4], hi[4];
    float cx = 0.f, cz = 0.f;
    for (int i = 0; i < 4; ++i) {
      lo[i] = {f[i][0], 0.f, f[i][1]};
      hi[i] = {f[i][0], height, f[i][1]};
      cx += 0.25f * f[i][0];
      cz += 0.25f * f[i][1];
    }
    quad(hi[0], hi[1], hi[2], hi[3], {0.f, 1.f, 0.f}, material);
    for (int i = 0; i < 4; ++i) {
      const int j = (i + 1) % 4;
      Vec3 out = cross(hi[j] - lo[i], lo[j] - lo[i]);
      out = normalize(Vec3{out.x, 0.f, out.z});
      const Vec3 mid{0.5f * (f[i][0] + f[j][0]) - cx, 0.f, 0.5f * (f[i][1] + f[j][1]) - cz};
      if (dot(out, mid) < 0.f) out = -out;
      quad(lo[i], lo[j], hi[j], hi[i], out, material);
    }
  }
};

Scene make_cornell(float aspect = 0.f);  // aspect > 0: every quad split into a needle and a sliver (slivers)
constexpr int kVoxelWaterLevel = 10;     // voxels: the water surface
Scene make_voxels(int size);
float hash01(uint32_t a, uint32_t b, uint32_t c);

// The stiff-case catalogue (stiff_cases.cpp).
const ParamTable& far_params();
Scene make_far_scene(ParamSet& params);
const ParamTable& scaled_params();
Scene make_scaled_scene(ParamSet& params);
const ParamTable& slivers_params();
Scene make_slivers_scene(ParamSet& params);
Scene make_coplanar_scene(ParamSet& params);
const ParamTable& flat_params();
Scene make_flat_scene(ParamSet& params);
const ParamTable& grazing_params();
Scene make_grazing_scene(ParamSet& params);
const ParamTable& pile_params();
Scene make_pile_scene(ParamSet& params);

}  // namespace raycoh::procedural
