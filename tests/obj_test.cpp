// The OBJ loader on small files written here: bad face and normal indices are errors naming the file,
// polygons fan into triangles, missing MTL files fall back to a default material, MTL values map onto
// classified materials.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/error.h"
#include "scenes/scene.h"
#include "tests/scenes_test_util.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

namespace fs = std::filesystem;

using test::expect_load_error;
using test::expect_valid;

// --- OBJ ------------------------------------------------------------------------------------------------------

fs::path write_obj(const std::string& test, const std::string& name, const std::string& obj,
                   const std::string& mtl = "") {
  const fs::path dir = test::temp_dir(test);
  test::write_file(dir / name, obj);
  if (!mtl.empty()) test::write_file(dir / "m.mtl", mtl);
  return dir / name;
}

TEST(ObjLoader, BadFaceIndicesAreErrors) {
  const std::string verts = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n";
  expect_load_error(write_obj("obj_bad", "big.obj", verts + "f 1 2 9\n"), "vertex 9");
  expect_load_error(write_obj("obj_bad", "quad.obj", verts + "f 1 2 3 7\n"), "vertex 7");
  expect_load_error(write_obj("obj_bad", "relative.obj", verts + "f -1 -2 -9\n"));
  expect_load_error(write_obj("obj_bad", "zero.obj", verts + "f 0 1 2\n"));
  expect_load_error(write_obj("obj_bad", "normal.obj", verts + "vn 0 0 1\nf 1//1 2//1 3//5\n"), "normal 5");
  expect_load_error(write_obj("obj_bad", "nofaces.obj", verts), "no triangles");
}

TEST(ObjLoader, NonNumericOrMissingCoordinatesAreErrorsNamingTheLine) {
  const std::string tail = "v 0 1 0\nf 1 2 3\n";
  expect_load_error(write_obj("obj_numbers", "word.obj", "v 0 0 0\nv 1 zero 0\n" + tail), "line 2: 'zero'");
  expect_load_error(write_obj("obj_numbers", "comma.obj", "v 0 0 0\nv 1,5 0 0\n" + tail), "line 2: '1,5'");
  expect_load_error(write_obj("obj_numbers", "short.obj", "v 0 0 0\nv 1 0\n" + tail), "line 2: 'v' needs");
  expect_load_error(write_obj("obj_numbers", "nan.obj", "v 0 0 0\nv 1 nan 0\n" + tail), "line 2");
  expect_load_error(write_obj("obj_numbers", "normal.obj", "v 0 0 0\nv 1 0 0\n" + tail + "vn 0 1\n"), "line 5");
  // Comments, w and vertex colours are fine.
  const Scene s =
      load_scene(write_obj("obj_numbers", "ok.obj", "v 0 0 0 1 # w\nv 1 0 0 0.5 0.5 0.5\nvt 0.5\n" + tail).string());
  EXPECT_EQ(s.triangle_count(), 1u);
}

TEST(ObjLoader, PolygonsNormalsAndMissingMtl) {
  // A pentagon fans into 3 triangles, a quad into 2; the quad has normals, the pentagon gets generated ones.
  const std::string obj =
      "mtllib nowhere.mtl\nusemtl ghost\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -0.5 0.5 0\nvn 0 0 2\n"
      "f 1 2 3 4 5\nf 1//1 2//1 3//1 4//1\n";
  const Scene s = load_scene(write_obj("obj_poly", "poly.obj", obj).string());
  EXPECT_EQ(s.triangle_count(), 5u);
  expect_valid(s);
  EXPECT_TRUE(s.generated_normals);
  EXPECT_FALSE(s.camera.from_file);
  for (const Vec3& n : s.normals) EXPECT_NEAR(n.z, 1.f, 1e-6f);
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].name, "default");
}

TEST(ObjLoader, MtlMapping) {
  const std::string mtl =
      "newmtl matte\nKd 0.5 0.4 0.3\nKs 0 0 0\nNs 500\n"
      "newmtl shiny\nKd 0.5 0.5 0.5\nKs 0.5 0.5 0.5\nNs 1000\n"  // (2/1002)^(1/4) = 0.211 -> glossy
      "newmtl mirror\nKd 0 0 0\nKs 0.9 0.9 0.9\nNs 1000000\n"    // roughness 0.038
      "newmtl lamp\nKd 1 1 1\nKe 5 5 5\n"
      "newmtl window\nKd 0 0 0\nTf 0.2 0.8 0.2\nillum 7\nNi 1.45\n"
      "newmtl veil\nKd 0.8 0.8 0.8\nd 0.25\n";
  std::string obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n";
  for (const char* m : {"matte", "shiny", "mirror", "lamp", "window", "veil"})
    obj += fmt::format("usemtl {}\nf 1 2 3\n", m);
  const Scene s = load_scene(write_obj("obj_mtl", "mtl.obj", obj, mtl).string());
  ASSERT_EQ(s.materials.size(), 6u);
  const auto& m = s.materials;
  EXPECT_EQ(m[0].cls, MaterialClass::Diffuse);
  EXPECT_FLOAT_EQ(m[0].roughness, 1.f);
  EXPECT_FLOAT_EQ(m[0].base_color.y, 0.4f);
  EXPECT_NEAR(m[1].roughness, std::pow(2.f / 1002.f, 0.25f), 1e-6f);
  EXPECT_EQ(m[1].cls, MaterialClass::Glossy);
  EXPECT_FLOAT_EQ(m[2].metallic, 1.f);
  EXPECT_FLOAT_EQ(m[2].base_color.x, 0.9f);
  EXPECT_EQ(m[2].cls, MaterialClass::Specular);
  EXPECT_EQ(m[3].cls, MaterialClass::Emissive);
  EXPECT_EQ(m[4].cls, MaterialClass::Transmissive);
  EXPECT_FLOAT_EQ(m[4].ior, 1.45f);
  EXPECT_TRUE(m[4].thin_walled);
  EXPECT_FLOAT_EQ(m[4].base_color.y, 0.8f);
  EXPECT_FLOAT_EQ(m[5].transmission, 0.75f);
  EXPECT_FALSE(m[5].thin_walled);
}

}  // namespace
}  // namespace raycoh
