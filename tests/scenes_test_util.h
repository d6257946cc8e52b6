// Helpers shared by the scene-loading tests (gltf_test, obj_test, procedural_test, scene_features_test,
// shared_scenes_test): the checks every loaded scene must pass, the one-line error check for malformed input,
// and GltfWriter, a small writer of synthetic .glb/.gltf files whose raw JSON fragments allow malformed variants.
#pragma once

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/params.h"
#include "scenes/scene.h"
#include "tests/test_util.h"

namespace raycoh::test {

namespace fs = std::filesystem;

// The message names the input and is one line.
inline void expect_load_error(const fs::path& file, const std::string& must_contain = "") {
  const std::string msg = error_of([&] { load_scene(file.string()); });
  EXPECT_NE(msg, "no error") << file;
  EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  if (!must_contain.empty()) {
    EXPECT_NE(msg.find(must_contain), std::string::npos) << msg;
  }
}

inline std::array<size_t, 5> used_class_counts(const Scene& s) {
  const SceneFeatures f = analyse(s);
  return {f.materials_per_class[0], f.materials_per_class[1], f.materials_per_class[2], f.materials_per_class[3],
          f.materials_per_class[4]};
}

inline void expect_valid(const Scene& s) {
  ASSERT_GT(s.triangle_count(), 0u);
  ASSERT_EQ(s.indices.size(), 3 * s.triangle_count());
  ASSERT_EQ(s.tri_material.size(), s.triangle_count());
  ASSERT_EQ(s.normals.size(), s.positions.size());
  for (uint32_t i : s.indices) ASSERT_LT(i, s.positions.size());
  for (uint32_t m : s.tri_material) ASSERT_LT(m, s.materials.size());
  for (const Vec3& p : s.positions) ASSERT_TRUE(is_finite(p));
  for (const Vec3& n : s.normals) ASSERT_NEAR(length(n), 1.f, 1e-4f);
  for (const Material& m : s.materials) EXPECT_EQ(m.cls, classify_material(m)) << m.name;
  // An emitter's material emits, or (emissive texture) the mean of its emissive texels does.
  for (uint32_t t : s.emissive_tris) {
    if (s.textures.emission_textured(t))
      EXPECT_GT(max_component(s.textures.tri_emission[t]), 0.f) << "triangle " << t;
    else
      EXPECT_EQ(s.materials[s.tri_material[t]].cls, MaterialClass::Emissive) << "triangle " << t;
  }
  if (!s.textures.empty()) {
    ASSERT_EQ(s.textures.tri_material.size(), s.triangle_count());
    ASSERT_EQ(s.textures.tri_uv.size(), 12 * s.triangle_count());
    ASSERT_EQ(s.textures.tri_tangent.size(), 4 * s.triangle_count());
  }
  EXPECT_FALSE(s.bounds.empty());
  EXPECT_GT(length(s.camera.target - s.camera.eye), 0.f);
  EXPECT_TRUE(s.env.enabled || !s.emissive_tris.empty() || !s.lights.empty());
  EXPECT_NEAR(length(s.env.sun_dir), 1.f, 1e-5f);
}

// Whether some loader note contains `text`.
inline bool has_note(const Scene& s, const std::string& text) {
  for (const std::string& n : s.load_notes)
    if (n.find(text) != std::string::npos) return true;
  return false;
}

// --- A small glTF writer for the synthetic cases --------------------------------------------------------------

template <typename T>
inline void append(std::string& bin, const std::vector<T>& values) {
  const size_t at = bin.size();
  bin.resize(at + values.size() * sizeof(T));
  std::memcpy(bin.data() + at, values.data(), values.size() * sizeof(T));
  while (bin.size() % 4) bin.push_back('\0');
}

// Accessors each get their own buffer view over one buffer; raw JSON fragments allow malformed variants.
struct GltfWriter {
  std::string bin;
  std::vector<std::string> views, accessors;
  std::string meshes = "[]", nodes = "[{\"mesh\":0}]", scenes = "[{\"nodes\":[0]}]", materials, cameras, extra;

  template <typename T>
  int add(const std::vector<T>& values, int component_type, const char* type) {
    const size_t offset = bin.size();
    append(bin, values);
    const int comps = std::string(type) == "VEC3" ? 3 : 1;
    views.push_back(
        fmt::format("{{\"buffer\":0,\"byteOffset\":{},\"byteLength\":{}}}", offset, values.size() * sizeof(T)));
    accessors.push_back(fmt::format("{{\"bufferView\":{},\"componentType\":{},\"count\":{},\"type\":\"{}\"}}",
                                    views.size() - 1, component_type, values.size() / comps, type));
    return static_cast<int>(accessors.size()) - 1;
  }
  int positions(const std::vector<float>& xyz) { return add(xyz, 5126, "VEC3"); }
  int u16(const std::vector<uint16_t>& v) { return add(v, 5123, "SCALAR"); }
  int u8(const std::vector<uint8_t>& v) { return add(v, 5121, "SCALAR"); }
  int u32(const std::vector<uint32_t>& v) { return add(v, 5125, "SCALAR"); }

  std::string json(const std::string& buffer_uri = "") const {
    std::string out = "{\"asset\":{\"version\":\"2.0\"}";
    out += fmt::format(",\"buffers\":[{{\"byteLength\":{}{}}}]", bin.size(),
                       buffer_uri.empty() ? "" : ",\"uri\":\"" + buffer_uri + "\"");
    out += ",\"bufferViews\":[" + join(views, ",") + "]";
    out += ",\"accessors\":[" + join(accessors, ",") + "]";
    out += ",\"meshes\":" + meshes + ",\"nodes\":" + nodes;
    if (!scenes.empty()) out += ",\"scenes\":" + scenes + ",\"scene\":0";
    if (!materials.empty()) out += ",\"materials\":" + materials;
    if (!cameras.empty()) out += ",\"cameras\":" + cameras;
    return out + extra + "}";
  }

  std::string glb() const {
    std::string j = json();
    while (j.size() % 4) j.push_back(' ');
    auto u32le = [](std::string& s, uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); };
    std::string out = "glTF";
    u32le(out, 2);
    u32le(out, static_cast<uint32_t>(12 + 8 + j.size() + 8 + bin.size()));
    u32le(out, static_cast<uint32_t>(j.size()));
    out += "JSON" + j;
    u32le(out, static_cast<uint32_t>(bin.size()));
    out += std::string("BIN\0", 4) + bin;
    return out;
  }

  fs::path write(const std::string& test, const std::string& name) const {
    const fs::path file = test::temp_dir(test) / name;
    test::write_file(file, glb());
    return file;
  }
};

inline std::string mesh_json(int pos, int idx = -1, const std::string& more = "") {
  return fmt::format("[{{\"primitives\":[{{\"attributes\":{{\"POSITION\":{}}}{}{}}}]}}]", pos,
                     idx >= 0 ? fmt::format(",\"indices\":{}", idx) : "", more);
}

// One triangle in the z = 0 plane, facing +z.
inline const std::vector<float> kTri = {0, 0, 0, 1, 0, 0, 0, 1, 0};

inline GltfWriter one_triangle() {
  GltfWriter w;
  const int pos = w.positions(kTri);
  const int idx = w.u16({0, 1, 2});
  w.meshes = mesh_json(pos, idx);
  return w;
}

}  // namespace raycoh::test
