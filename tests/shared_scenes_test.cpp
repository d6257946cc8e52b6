// The shared glTF/OBJ scenes beside the project (skipped where absent): every .glb loads with the README's
// triangle count, the Cornell box's OBJ and GLB agree, cameras and material extensions come from the files, a
// folder stands for its one scene file.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <map>
#include <string>

#include "core/error.h"
#include "scenes/scene.h"
#include "tests/scenes_test_util.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

namespace fs = std::filesystem;

using test::expect_valid;
using test::used_class_counts;

// --- Shared scenes ---------------------------------------------------------------------------------------------

const std::map<std::string, size_t> kSharedTriangles = {
    {"cornell_box", 36},
    {"sibenik", 75284},
    {"lost_empire", 224998},
    {"crytek_sponza", 279163},
    {"conference", 331179},
    {"contemporary_bathroom", 572036},
    {"modern_living_room", 787232},
    {"country_kitchen", 1443517},
};

TEST(SharedScenes, EveryGlbLoadsWithTheReadmeTriangleCount) {
  const auto files = test::shared_scene_files();
  if (test::shared_scenes_dir().empty() || files.empty()) GTEST_SKIP() << "no shared scenes directory";
  size_t checked = 0;
  for (const fs::path& file : files) {
    const auto t0 = std::chrono::steady_clock::now();
    const Scene s = load_scene(file.string());
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto c = used_class_counts(s);
    std::printf("  %-22s %9zu triangles %6.3f s  diffuse %zu glossy %zu specular %zu transmissive %zu emissive %zu%s\n",
                s.name.c_str(), s.triangle_count(), seconds, c[0], c[1], c[2], c[3], c[4],
                s.env.enabled ? "  (sky + sun)" : "");
    expect_valid(s);
    EXPECT_TRUE(s.camera.from_file) << file;
    const auto it = kSharedTriangles.find(s.name);
    if (it == kSharedTriangles.end()) continue;
    EXPECT_EQ(s.triangle_count(), it->second) << file;
    ++checked;
  }
  EXPECT_EQ(checked, kSharedTriangles.size());
}

fs::path shared(const std::string& rel) {
  const fs::path dir = test::shared_scenes_dir();
  return dir.empty() ? fs::path{} : dir / rel;
}

TEST(SharedScenes, CornellObjAndGlbAgree) {
  const fs::path glb = shared("cornell_box/cornell_box.glb"), obj = shared("cornell_box/obj/CornellBox-Original.obj");
  if (glb.empty() || !fs::exists(glb) || !fs::exists(obj)) GTEST_SKIP() << "no shared cornell_box";
  const Scene a = load_scene(glb.string()), b = load_scene(obj.string());
  EXPECT_EQ(a.triangle_count(), b.triangle_count());
  EXPECT_EQ(used_class_counts(a), used_class_counts(b));
  std::map<std::string, MaterialClass> classes;
  for (const Material& m : a.materials) classes[m.name] = m.cls;
  for (const Material& m : b.materials) {
    ASSERT_TRUE(classes.count(m.name)) << m.name;
    EXPECT_EQ(classes[m.name], m.cls) << m.name;
  }
  // Ke = 17 12 4 in the MTL; emissiveFactor x KHR_materials_emissive_strength in the GLB.
  for (const Scene* s : {&a, &b}) {
    ASSERT_EQ(s->emissive_tris.size(), 2u);
    const Material& light = s->materials[s->tri_material[s->emissive_tris[0]]];
    EXPECT_NEAR(light.emission.x, 17.f, 1e-3f);
    EXPECT_NEAR(light.emission.y, 12.f, 1e-3f);
    EXPECT_NEAR(light.emission.z, 4.f, 1e-3f);
    EXPECT_FALSE(s->env.enabled);
  }
  EXPECT_EQ(a.bounds.lo.x, b.bounds.lo.x);
  EXPECT_EQ(a.bounds.hi.y, b.bounds.hi.y);
}

TEST(SharedScenes, CameraComesFromTheFile) {
  const fs::path glb = shared("cornell_box/cornell_box.glb");
  if (glb.empty() || !fs::exists(glb)) GTEST_SKIP() << "no shared cornell_box";
  const Scene s = load_scene(glb.string());
  EXPECT_TRUE(s.camera.from_file);
  EXPECT_NEAR(s.camera.eye.x, 0.f, 1e-5f);
  EXPECT_NEAR(s.camera.eye.y, 1.f, 1e-5f);
  EXPECT_NEAR(s.camera.eye.z, 3.5f, 1e-5f);
  const Vec3 d = normalize(s.camera.target - s.camera.eye);
  EXPECT_NEAR(d.z, -1.f, 1e-5f);
  EXPECT_NEAR(s.camera.up.y, 1.f, 1e-5f);
  EXPECT_NEAR(s.camera.vfov_deg, 45.f, 1e-3f);
  // The OBJ has no camera: default framing.
  const Scene o = load_scene(shared("cornell_box/obj/CornellBox-Original.obj").string());
  EXPECT_FALSE(o.camera.from_file);
}

TEST(SharedScenes, DirectoriesAndMaterialExtensions) {
  const fs::path dir = test::shared_scenes_dir();
  if (dir.empty()) GTEST_SKIP() << "no shared scenes directory";
  // A folder stands for its one top-level scene file (the OBJ copy sits in a subfolder).
  const Scene cornell = load_scene((dir / "cornell_box").string());
  EXPECT_EQ(cornell.name, "cornell_box");
  EXPECT_EQ(cornell.source, (dir / "cornell_box").string());
  EXPECT_EQ(load_scene((dir / "cornell_box" / "obj").string()).name, "CornellBox-Original");
  if (fs::exists(dir / "sibenik")) {
    // staklo_crveno has KHR_materials_volume (solid), staklo has none (thin pane); no emitters -> sky + sun.
    const Scene s = load_scene((dir / "sibenik").string());
    int seen = 0;
    for (const Material& m : s.materials) {
      if (m.name == "staklo_crveno") {
        EXPECT_FALSE(m.thin_walled);
        ++seen;
      }
      if (m.name == "staklo") {
        EXPECT_TRUE(m.thin_walled);
        EXPECT_EQ(m.cls, MaterialClass::Transmissive);
        ++seen;
      }
    }
    EXPECT_EQ(seen, 2);
    EXPECT_TRUE(s.env.enabled);
    EXPECT_TRUE(s.emissive_tris.empty());
  }
  if (fs::exists(dir / "lost_empire")) {
    // Weak lava emitters only: the sky + sun is added on top.
    const Scene s = load_scene((dir / "lost_empire").string());
    EXPECT_FALSE(s.emissive_tris.empty());
    EXPECT_TRUE(s.env.enabled);
  }
}

}  // namespace
}  // namespace raycoh
