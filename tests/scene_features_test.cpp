// The rules shared by every loader: material classification, finalize_scene (normals, default camera,
// validation errors, sky and sun), analyse (features and skipped stages), and load_scene's dispatch of
// directories and "path:sun=x/y/z" specs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "scenes/scene.h"
#include "tests/scenes_test_util.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

namespace fs = std::filesystem;

using test::error_of;
using test::expect_load_error;
using test::GltfWriter;
using test::one_triangle;

// --- Rules: classification, finalize_scene, analyse, load_scene dispatch -------------------------------------

TEST(Classification, Rules) {
  auto cls = [](float rough, float metal = 0.f, float trans = 0.f, Vec3 em = {}) {
    Material m;
    m.roughness = rough;
    m.metallic = metal;
    m.transmission = trans;
    m.emission = em;
    return classify_material(m);
  };
  EXPECT_EQ(cls(1.f), MaterialClass::Diffuse);
  EXPECT_EQ(cls(0.41f), MaterialClass::Diffuse);
  EXPECT_EQ(cls(kGlossyRoughness), MaterialClass::Glossy);
  EXPECT_EQ(cls(1.f, 0.5f), MaterialClass::Glossy);
  EXPECT_EQ(cls(1.f, 0.49f), MaterialClass::Diffuse);
  EXPECT_EQ(cls(kSpecularRoughness), MaterialClass::Specular);
  EXPECT_EQ(cls(0.f, 1.f), MaterialClass::Specular);
  EXPECT_EQ(cls(0.f, 0.f, 0.51f), MaterialClass::Transmissive);
  EXPECT_EQ(cls(0.f, 0.f, 0.5f), MaterialClass::Specular);
  EXPECT_EQ(cls(0.f, 0.f, 1.f, {0.f, 0.f, 1e-3f}), MaterialClass::Emissive);
  EXPECT_STREQ(to_string(MaterialClass::Transmissive), "transmissive");
  EXPECT_STREQ(to_string(MaterialClass::Emissive), "emissive");
}

Scene quad_scene(Vec3 offset, float scale) {
  Scene s;
  s.name = "quad";
  for (Vec3 p : {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{1, 1, 0}, Vec3{0, 1, 0}}) s.positions.push_back(offset + p * scale);
  s.indices = {0, 1, 2, 0, 2, 3};
  s.tri_material = {0, 0};
  s.materials.push_back(Material{"m"});
  return s;
}

TEST(Finalize, NormalsAreGeneratedRepairedAndNormalised) {
  Scene s = quad_scene({}, 1.f);
  finalize_scene(s);
  EXPECT_TRUE(s.generated_normals);
  for (const Vec3& n : s.normals) EXPECT_NEAR(n.z, 1.f, 1e-6f);

  Scene r = quad_scene({}, 1.f);
  r.normals = {{0, 0, 0}, {NAN, 0, 1}, {0, 0, 5}, {0, 1e-30f, 0}};
  finalize_scene(r);
  EXPECT_FALSE(r.generated_normals);
  for (const Vec3& n : r.normals) EXPECT_NEAR(n.z, 1.f, 1e-6f);
}

TEST(Finalize, DefaultCameraFramesTheBounds) {
  for (auto [offset, scale] : {std::pair{Vec3{0, 0, 0}, 1.f}, std::pair{Vec3{1e6f, -1e6f, 1e6f}, 1.f},
                               std::pair{Vec3{0, 0, 0}, 1e-6f}, std::pair{Vec3{3, 4, 5}, 1e4f}}) {
    Scene s = quad_scene(offset, scale);
    finalize_scene(s);
    EXPECT_FALSE(s.camera.from_file);
    const Vec3 c = s.bounds.center();
    EXPECT_EQ(s.camera.target.x, c.x);
    const float dist = length(s.camera.eye - s.camera.target);
    const float radius = 0.5f * length(s.bounds.extent());
    EXPECT_GT(dist, 0.f);
    // The bounding sphere fits in a 45-degree field of view.
    EXPECT_GE(dist * std::sin(22.5f * 3.14159265f / 180.f), radius * 0.999f);
    EXPECT_FLOAT_EQ(s.camera.vfov_deg, 45.f);
  }
  // A camera with NaNs is replaced.
  Scene s = quad_scene({}, 1.f);
  s.camera.eye = {NAN, 0, 0};
  s.camera.from_file = true;
  finalize_scene(s);
  EXPECT_FALSE(s.camera.from_file);
  EXPECT_TRUE(is_finite(s.camera.eye));
}

TEST(Finalize, ValidationErrorsNameTheScene) {
  Scene nan = quad_scene({}, 1.f);
  nan.source = "nan-scene";
  nan.positions[2].y = NAN;
  EXPECT_NE(error_of([&] { finalize_scene(nan); }).find("nan-scene"), std::string::npos);
  Scene range = quad_scene({}, 1.f);
  range.indices[4] = 9;
  EXPECT_NE(error_of([&] { finalize_scene(range); }).find("vertex 9"), std::string::npos);
  Scene none = quad_scene({}, 1.f);
  none.indices.clear();
  none.tri_material.clear();
  EXPECT_NE(error_of([&] { finalize_scene(none); }).find("no triangles"), std::string::npos);
  Scene mat = quad_scene({}, 1.f);
  mat.tri_material[1] = 3;
  EXPECT_NE(error_of([&] { finalize_scene(mat); }).find("material 3"), std::string::npos);
}

TEST(Finalize, SkyAndSunOnlyWithoutUsefulEmitters) {
  Scene dark = quad_scene({}, 1.f);
  finalize_scene(dark);
  EXPECT_TRUE(dark.env.enabled);
  EXPECT_GT(max_component(dark.env.sun_radiance), 0.f);
  EXPECT_GT(max_component(dark.env.sky_zenith), 0.f);
  EXPECT_NEAR(length(dark.env.sun_dir), 1.f, 1e-6f);

  Scene lit = quad_scene({}, 1.f);
  lit.materials.push_back(Material{"lamp"});
  lit.materials[1].emission = {5, 5, 5};
  lit.tri_material[1] = 1;
  finalize_scene(lit);
  EXPECT_FALSE(lit.env.enabled);
  EXPECT_EQ(lit.emissive_tris, std::vector<uint32_t>{1});

  Scene glow = lit;
  glow.materials[1].emission = {1e-4f, 1e-4f, 1e-4f};
  finalize_scene(glow);
  EXPECT_TRUE(glow.env.enabled);
  EXPECT_EQ(glow.emissive_tris.size(), 1u);
}

TEST(Analyse, OnlyUsedMaterialsCount) {
  Scene s = quad_scene({}, 1.f);
  Material glossy{"unused glossy"};
  glossy.roughness = 0.1f;
  s.materials.push_back(glossy);
  finalize_scene(s);
  const SceneFeatures f = analyse(s);
  EXPECT_FALSE(f.has_glossy);
  EXPECT_EQ(f.materials_per_class[0], 1u);
  EXPECT_TRUE(f.needs_env_light);
  EXPECT_EQ(f.triangles, 2u);
  const auto has = [&](const std::string& text) {
    return std::find(f.skipped_stages.begin(), f.skipped_stages.end(), text) != f.skipped_stages.end();
  };
  EXPECT_TRUE(has("hybrid groups: no glossy materials"));
  EXPECT_TRUE(has("texture decoding: scene has no textures"));
  EXPECT_FALSE(has("environment light: scene has emitters"));
}

TEST(LoadScene, DirectoriesPickOneFile) {
  const GltfWriter w = one_triangle();
  const fs::path both = test::temp_dir("dir_both"), two = test::temp_dir("dir_two"), none = test::temp_dir("dir_none"),
                 obj = test::temp_dir("dir_obj");
  test::write_file(both / "a.glb", w.glb());
  test::write_file(both / "b.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n");
  EXPECT_EQ(load_scene(both.string()).name, "a");
  test::write_file(obj / "only.OBJ", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_EQ(load_scene(obj.string()).name, "only");
  test::write_file(two / "a.glb", w.glb());
  test::write_file(two / "b.gltf", w.json());
  expect_load_error(two, "several");
  test::write_file(none / "readme.txt", "x");
  expect_load_error(none, "no .gltf");
}

// "path:sun=x/y/z" sets the sun of a file scene; bad values are errors naming the scene.
TEST(SceneSpec, FileScenesTakeASunDirection) {
  const auto dir = test::shared_scenes_dir();
  if (dir.empty()) GTEST_SKIP() << "no shared scenes";
  const std::string path = (dir / "sibenik" / "sibenik.glb").string();
  const Scene s = load_scene(path + ":sun=0/2/0");
  EXPECT_TRUE(s.env.enabled);
  EXPECT_FLOAT_EQ(s.env.sun_dir.y, 1.f);
  EXPECT_EQ(s.source, path + ":sun=0/2/0");
  EXPECT_THROW(load_scene(path + ":sun=0/0"), Error);
  EXPECT_THROW(load_scene(path + ":sun=0/0/0"), Error);
  EXPECT_THROW(load_scene(path + ":moon=1/1/1"), Error);
  EXPECT_NO_THROW(check_scene_spec("--scenes", path + ":sun=1/1/1"));
  EXPECT_THROW(check_scene_spec("--scenes", "/no/such.glb:sun=1/1/1"), Error);
}

}  // namespace
}  // namespace raycoh
