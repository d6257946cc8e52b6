// The procedural built-in scenes (cornell, voxels): deterministic and valid, the expected materials and
// lighting, a voxel landscape without duplicate or hidden faces, and checked parameters.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <set>
#include <string>
#include <vector>

#include "core/error.h"
#include "scenes/scene.h"
#include "tests/scenes_test_util.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

using test::error_of;
using test::expect_valid;
using test::used_class_counts;

// --- Procedural scenes ----------------------------------------------------------------------------------------

bool identical(const Scene& a, const Scene& b) {
  auto same_vecs = [](const std::vector<Vec3>& x, const std::vector<Vec3>& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(Vec3)) == 0;
  };
  if (!same_vecs(a.positions, b.positions) || !same_vecs(a.normals, b.normals)) return false;
  if (a.indices != b.indices || a.tri_material != b.tri_material || a.emissive_tris != b.emissive_tris) return false;
  if (a.materials.size() != b.materials.size()) return false;
  for (size_t i = 0; i < a.materials.size(); ++i)
    if (a.materials[i].name != b.materials[i].name || a.materials[i].cls != b.materials[i].cls ||
        std::memcmp(&a.materials[i].base_color, &b.materials[i].base_color, sizeof(Vec3)) != 0)
      return false;
  return std::memcmp(&a.camera.eye, &b.camera.eye, sizeof(Vec3)) == 0 && a.env.enabled == b.env.enabled;
}

TEST(Procedural, DeterministicAndValid) {
  for (const char* spec : {"cornell", "voxels", "voxels:size=4", "voxels:size=37"}) {
    const Scene a = load_scene(spec), b = load_scene(spec);
    EXPECT_TRUE(identical(a, b)) << spec;
    expect_valid(a);
    EXPECT_EQ(a.source, spec);
    EXPECT_EQ(a.degenerate_tris, 0u) << spec;
  }
}

TEST(Procedural, CornellHasMixedMaterialsAndALight) {
  const Scene s = load_scene("cornell");
  EXPECT_EQ(s.name, "cornell");
  EXPECT_EQ(s.triangle_count(), 32u);
  const auto c = used_class_counts(s);
  EXPECT_EQ(c[static_cast<int>(MaterialClass::Glossy)], 1u);
  EXPECT_EQ(c[static_cast<int>(MaterialClass::Emissive)], 1u);
  EXPECT_EQ(s.emissive_tris.size(), 2u);
  EXPECT_FALSE(s.env.enabled);
  const SceneFeatures f = analyse(s);
  const auto has = [&](const std::string& text) {
    return std::find(f.skipped_stages.begin(), f.skipped_stages.end(), text) != f.skipped_stages.end();
  };
  EXPECT_TRUE(has("transmission handling: no transmissive materials"));
  EXPECT_TRUE(has("environment light: scene has emitters"));
  EXPECT_FALSE(has("hybrid groups: no glossy materials"));
  // Every wall faces into the box: the camera (outside the open front) sees the back wall's front side.
  EXPECT_GT(s.camera.eye.z, 1.f);
}

TEST(Procedural, VoxelsLandscape) {
  const Scene s = load_scene("voxels");
  EXPECT_EQ(s.name, "voxels");
  EXPECT_TRUE(s.emissive_tris.empty());
  EXPECT_TRUE(s.env.enabled);
  EXPECT_GT(s.env.sun_radiance.x, 0.f);
  const auto c = used_class_counts(s);
  EXPECT_GE(c[static_cast<int>(MaterialClass::Diffuse)], 3u);
  EXPECT_GE(c[static_cast<int>(MaterialClass::Specular)], 1u);  // water
  EXPECT_GE(c[static_cast<int>(MaterialClass::Glossy)], 1u);
  EXPECT_EQ(s.bounds.lo.x, 0.f);
  EXPECT_EQ(s.bounds.hi.x, 64.f);
  // No face is emitted twice and none lies between two blocks: every quad centre (with its normal) is unique.
  std::set<std::array<float, 6>> faces;
  for (size_t t = 0; t < s.triangle_count(); t += 2) {
    const uint32_t* i = &s.indices[3 * t];
    const Vec3 c0 = (s.positions[i[0]] + s.positions[i[2]]) * 0.5f;
    const Vec3 n = s.normals[i[0]];
    EXPECT_TRUE(faces.insert({c0.x, c0.y, c0.z, n.x, n.y, n.z}).second);
  }
  for (const auto& f : faces) EXPECT_FALSE(faces.count({f[0], f[1], f[2], -f[3], -f[4], -f[5]}));
  // The camera looks down on the landscape.
  EXPECT_GT(s.camera.eye.y, s.camera.target.y);
}

TEST(Procedural, ParametersAreChecked) {
  EXPECT_NE(error_of([] { load_scene("voxels:size=3"); }).find("[4, 1024]"), std::string::npos);
  EXPECT_NE(error_of([] { load_scene("voxels:size=1025"); }).find("[4, 1024]"), std::string::npos);
  EXPECT_NE(error_of([] { load_scene("voxels:size=big"); }).find("scene 'voxels'"), std::string::npos);
  EXPECT_NE(error_of([] { load_scene("voxels:sise=8"); }).find("valid parameters: size"), std::string::npos);
  EXPECT_NE(error_of([] { load_scene("cornell:size=8"); }).find("scene 'cornell'"), std::string::npos);
  EXPECT_NE(error_of([] { load_scene("sponge"); }).find("built-ins: cornell, voxels"), std::string::npos);
  EXPECT_NE(error_of([] { make_builtin_scene("sponge"); }).find("cornell, voxels"), std::string::npos);
  EXPECT_NE(error_of([] { builtin_scene_summary("sponge"); }).find("cornell, voxels"), std::string::npos);
  EXPECT_EQ(builtin_scene_names(), (std::vector<std::string>{"cornell", "voxels", "far", "scaled", "slivers",
                                                             "coplanar", "flat", "grazing", "pile"}));
  EXPECT_NE(builtin_scene_summary("voxels").find("size=64 ([4, 1024])"), std::string::npos);
  EXPECT_FALSE(builtin_scene_summary("cornell").empty());
}

}  // namespace
}  // namespace raycoh
