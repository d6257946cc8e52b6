// Conformance of the glTF loader on the glTF sample folder (tests/test_util.h gltf_samples_dir: 42 Khronos sample
// files; skipped where absent). The folder's README is the reference: its table gives each file's true triangle
// count (from an independent reader), the triangles EXT_mesh_gpu_instancing adds, zero-area triangles and the
// extensions it requires. Every file must load with exactly that count (less the triangles an alpha MASK cuts
// out, which the loader counts) or, for the Draco variants, be refused with an error naming the extension.
// Textured materials must be classified from their texels: DamagedHelmet emits from a few hundred triangles, not
// all 15,452. Punctual lights and alpha MASK cut-outs are read (LightsPunctualLamp, GlassVaseFlowers).
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "core/error.h"
#include "scenes/scene.h"
#include "tests/scenes_test_util.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

namespace fs = std::filesystem;

fs::path samples_dir() {
  const fs::path p = test::gltf_samples_dir();
  return !p.empty() && fs::exists(p / "README.md") ? p : fs::path{};
}

struct SampleRow {
  std::string file, features;
  size_t triangles = 0, instanced_extra = 0, zero_area = 0;
  bool refused = false;  // requires an extension the loader cannot decode
};

// The README's table: | `file` | true triangles | features | material inputs |
std::vector<SampleRow> read_table(const fs::path& readme) {
  std::ifstream in(readme);
  std::vector<SampleRow> rows;
  const std::regex row(R"(^\| `([^`]+)` \| (\d+) \| ([^|]*) \|)");
  const std::regex extra(R"(EXT_mesh_gpu_instancing extra tris (\d+))"), zero(R"(zero-area tris (\d+))");
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (!std::regex_search(line, m, row)) continue;
    SampleRow r;
    r.file = m[1];
    r.triangles = std::stoul(m[2]);
    r.features = m[3];
    std::smatch x;
    if (std::regex_search(r.features, x, extra)) r.instanced_extra = std::stoul(x[1]);
    if (std::regex_search(r.features, x, zero)) r.zero_area = std::stoul(x[1]);
    r.refused = r.features.find("requires KHR_draco_mesh_compression") != std::string::npos;
    rows.push_back(r);
  }
  return rows;
}

const Scene* find(const std::vector<std::pair<std::string, Scene>>& scenes, const std::string& file) {
  for (const auto& [f, s] : scenes)
    if (f == file) return &s;
  return nullptr;
}

// Nothing silent: every extension and unsupported feature the README lists for file `r` is named in the notes.
void expect_features_noted(const Scene& s, const SampleRow& r) {
  for (const char* ext :
       {"KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_clearcoat", "KHR_materials_specular",
        "KHR_lights_punctual", "KHR_texture_transform", "KHR_mesh_quantization", "EXT_mesh_gpu_instancing", "KHR_xmp"})
    if (r.features.find(ext) != std::string::npos) {
      EXPECT_TRUE(test::has_note(s, std::string("extension ") + ext)) << ext;
    }
  if (r.features.find("line prims") != std::string::npos) {
    EXPECT_TRUE(test::has_note(s, "line primitive"));
  }
  if (r.features.find("point prims") != std::string::npos) {
    EXPECT_TRUE(test::has_note(s, "point primitive"));
  }
  if (r.features.find("skins") != std::string::npos) {
    EXPECT_TRUE(test::has_note(s, "skin"));
  }
}

// What some files' scenes hold beyond their triangle counts: materials from textures, lights, alpha MASK and
// instancing.
void expect_scene_details(const std::vector<std::pair<std::string, Scene>>& loaded) {
  // Materials from textures: the helmet's emissive texture is dark but for a few lights.
  if (const Scene* helmet = find(loaded, "DamagedHelmet/glTF-Binary/DamagedHelmet.glb")) {
    EXPECT_GT(helmet->emissive_tris.size(), 0u);
    EXPECT_LT(helmet->emissive_tris.size(), 1000u);
    EXPECT_TRUE(helmet->env.enabled);  // its weak emitters do not light it
  }
  // The corset is cloth and leather with metal hardware: about a quarter of its metallic texels are lit (the
  // factor alone, metallic 1, made every triangle a rough metal). The hardware is finely triangulated, so the
  // share is measured by area.
  if (const Scene* corset = find(loaded, "Corset/glTF/Corset.gltf")) {
    double metal = 0, total = 0;
    for (size_t t = 0; t < corset->triangle_count(); ++t) {
      const uint32_t* i = &corset->indices[3 * t];
      const Vec3 a = corset->positions[i[0]], b = corset->positions[i[1]], c = corset->positions[i[2]];
      const double area = length(cross(b - a, c - a));
      total += area;
      if (corset->materials[corset->tri_material[t]].metallic >= 0.5f) metal += area;
    }
    EXPECT_GT(metal, 0.05 * total);
    EXPECT_LT(metal, 0.5 * total);
  }
  // Metal and transmission: the transmission test's glass stays transmissive.
  if (const Scene* t = find(loaded, "TransmissionTest/glTF-Binary/TransmissionTest.glb")) {
    EXPECT_GT(test::used_class_counts(*t)[static_cast<int>(MaterialClass::Transmissive)], 0u);
  }
  // Punctual lights light the lamp; no sky is substituted.
  if (const Scene* lamp = find(loaded, "LightsPunctualLamp/glTF/LightsPunctualLamp.gltf")) {
    EXPECT_EQ(lamp->lights.size(), 5u);
    EXPECT_FALSE(lamp->env.enabled);
  }
  // Alpha MASK leaves and petals are cut out per texel at every hit, not removed.
  if (const Scene* vase = find(loaded, "GlassVaseFlowers/glTF-Binary/GlassVaseFlowers.glb")) {
    EXPECT_EQ(vase->alpha_cut_tris, 0u);
    EXPECT_GT(vase->alpha.masked_tris, 1000u);
  }
  // Instancing is flattened and reported.
  if (const Scene* inst = find(loaded, "SimpleInstancing/glTF-Binary/SimpleInstancing.glb")) {
    EXPECT_TRUE(test::has_note(*inst, "EXT_mesh_gpu_instancing: 125 instance"));
  }
}

TEST(GltfSamples, EveryFileLoadsWithItsTrueTriangleCountOrIsRefusedByName) {
  const fs::path dir = samples_dir();
  if (dir.empty()) GTEST_SKIP() << "no ../shared/gltf-samples";
  const std::vector<SampleRow> rows = read_table(dir / "README.md");
  ASSERT_EQ(rows.size(), 42u) << "README table rows";
  std::vector<std::pair<std::string, Scene>> loaded;
  for (const SampleRow& r : rows) {
    const fs::path file = dir / r.file;
    SCOPED_TRACE(r.file);
    if (r.refused) {
      test::expect_load_error(file, "KHR_draco_mesh_compression");
      continue;
    }
    Scene s;
    try {
      s = load_scene(file.string());
    } catch (const Error& e) {
      ADD_FAILURE() << e.what();
      continue;
    }
    test::expect_valid(s);
    EXPECT_EQ(s.triangle_count() + s.alpha_cut_tris, r.triangles + r.instanced_extra);
    EXPECT_EQ(s.degenerate_tris, r.zero_area);
    expect_features_noted(s, r);
    loaded.emplace_back(r.file, std::move(s));
  }

  expect_scene_details(loaded);
}

}  // namespace
}  // namespace raycoh
