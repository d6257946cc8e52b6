// Scene loading: the shared glTF/OBJ scenes, malformed files written here (each must give one Error line that
// names the file), the procedural built-ins, material classification, normals, camera and lighting rules.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <set>

#include "core/error.h"
#include "core/params.h"
#include "scenes/scene.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

namespace fs = std::filesystem;

using test::error_of;

// The message names the input and is one line.
void expect_load_error(const fs::path& file, const std::string& must_contain = "") {
  const std::string msg = error_of([&] { load_scene(file.string()); });
  EXPECT_NE(msg, "no error") << file;
  EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  if (!must_contain.empty()) {
    EXPECT_NE(msg.find(must_contain), std::string::npos) << msg;
  }
}

std::array<size_t, 5> used_class_counts(const Scene& s) {
  const SceneFeatures f = analyse(s);
  return {f.materials_per_class[0], f.materials_per_class[1], f.materials_per_class[2], f.materials_per_class[3],
          f.materials_per_class[4]};
}

void expect_valid(const Scene& s) {
  ASSERT_GT(s.triangle_count(), 0u);
  ASSERT_EQ(s.indices.size(), 3 * s.triangle_count());
  ASSERT_EQ(s.tri_material.size(), s.triangle_count());
  ASSERT_EQ(s.normals.size(), s.positions.size());
  for (uint32_t i : s.indices) ASSERT_LT(i, s.positions.size());
  for (uint32_t m : s.tri_material) ASSERT_LT(m, s.materials.size());
  for (const Vec3& p : s.positions) ASSERT_TRUE(is_finite(p));
  for (const Vec3& n : s.normals) ASSERT_NEAR(length(n), 1.f, 1e-4f);
  for (const Material& m : s.materials) EXPECT_EQ(m.cls, classify_material(m)) << m.name;
  for (uint32_t t : s.emissive_tris) EXPECT_EQ(s.materials[s.tri_material[t]].cls, MaterialClass::Emissive);
  EXPECT_FALSE(s.bounds.empty());
  EXPECT_GT(length(s.camera.target - s.camera.eye), 0.f);
  EXPECT_TRUE(s.env.enabled || !s.emissive_tris.empty());
  EXPECT_NEAR(length(s.env.sun_dir), 1.f, 1e-5f);
}

// --- A small glTF writer for the synthetic cases --------------------------------------------------------------

template <typename T>
void append(std::string& bin, const std::vector<T>& values) {
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

std::string mesh_json(int pos, int idx = -1, const std::string& more = "") {
  return fmt::format("[{{\"primitives\":[{{\"attributes\":{{\"POSITION\":{}}}{}{}}}]}}]", pos,
                     idx >= 0 ? fmt::format(",\"indices\":{}", idx) : "", more);
}

// One triangle in the z = 0 plane, facing +z.
const std::vector<float> kTri = {0, 0, 0, 1, 0, 0, 0, 1, 0};

GltfWriter one_triangle() {
  GltfWriter w;
  const int pos = w.positions(kTri);
  const int idx = w.u16({0, 1, 2});
  w.meshes = mesh_json(pos, idx);
  return w;
}

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

// --- Synthetic glTF: good inputs ----------------------------------------------------------------------------

TEST(GltfLoader, IndexTypesAndNonIndexed) {
  for (int kind = 0; kind < 4; ++kind) {
    GltfWriter w;
    const int pos = w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
    int idx = -1;
    if (kind == 0) idx = w.u8({0, 1, 2, 2, 1, 3});
    if (kind == 1) idx = w.u16({0, 1, 2, 2, 1, 3});
    if (kind == 2) idx = w.u32({0, 1, 2, 2, 1, 3});
    w.meshes = mesh_json(pos, idx);
    const Scene s = load_scene(w.write("gltf_index_types", fmt::format("k{}.glb", kind)).string());
    EXPECT_EQ(s.triangle_count(), kind == 3 ? 1u : 2u) << kind;  // non-indexed: 4 vertices make 1 triangle
    expect_valid(s);
    EXPECT_TRUE(s.generated_normals);
    EXPECT_NEAR(s.normals[0].z, 1.f, 1e-6f);
    EXPECT_EQ(s.materials[s.tri_material[0]].name, "default");
    EXPECT_EQ(s.materials[s.tri_material[0]].cls, MaterialClass::Diffuse);
  }
}

TEST(GltfLoader, JsonGltfWithExternalBuffer) {
  GltfWriter w = one_triangle();
  const fs::path dir = test::temp_dir("gltf_json");
  test::write_file(dir / "tri.bin", w.bin);
  test::write_file(dir / "tri.gltf", w.json("tri.bin"));
  EXPECT_EQ(load_scene((dir / "tri.gltf").string()).triangle_count(), 1u);
  // Upper-case extension.
  test::write_file(dir / "TRI2.GLB", w.glb());
  EXPECT_EQ(load_scene((dir / "TRI2.GLB").string()).name, "TRI2");
}

TEST(GltfLoader, NodeHierarchyTransformsPositionsAndNormals) {
  GltfWriter w;
  const int pos = w.positions(kTri);
  const int nrm = w.add(std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1}, 5126, "VEC3");
  const int idx = w.u16({0, 1, 2});
  w.meshes = fmt::format(R"([{{"primitives":[{{"attributes":{{"POSITION":{0},"NORMAL":{1}}},"indices":{2}}}]}}])", pos,
                         nrm, idx);
  // Node 0: translate (10, 0, 0), child node 1 rotated 90 degrees about +y, scaled 2 in x.
  // Node 2: mirrored (scale x = -1).
  w.nodes = R"([{"translation":[10,0,0],"children":[1]},
                {"rotation":[0,0.70710678,0,0.70710678],"scale":[2,1,1],"mesh":0},
                {"scale":[-1,1,1],"mesh":0}])";
  w.scenes = R"([{"nodes":[0,2]}])";
  const Scene s = load_scene(w.write("gltf_nodes", "nodes.glb").string());
  ASSERT_EQ(s.triangle_count(), 2u);
  expect_valid(s);
  // Child: p' = T * R * S * p; x = (1, 0, 0) -> S -> (2, 0, 0) -> R(90 about y) -> (0, 0, -2) -> T -> (10, 0, -2).
  EXPECT_NEAR(s.positions[1].x, 10.f, 1e-5f);
  EXPECT_NEAR(s.positions[1].z, -2.f, 1e-5f);
  // Normal (0, 0, 1) -> R -> (1, 0, 0).
  EXPECT_NEAR(s.normals[0].x, 1.f, 1e-5f);
  // Geometric normal of every triangle agrees with its shading normal, mirrored one included.
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    const uint32_t* i = &s.indices[3 * t];
    const Vec3 ng = cross(s.positions[i[1]] - s.positions[i[0]], s.positions[i[2]] - s.positions[i[0]]);
    EXPECT_GT(dot(ng, s.normals[i[0]]), 0.f) << t;
  }
  EXPECT_NEAR(s.positions[4].x, -1.f, 1e-6f);
}

TEST(GltfLoader, NonUniformScaleUsesInverseTranspose) {
  GltfWriter w;
  const int pos = w.positions(kTri);
  const float r = 1.f / std::sqrt(2.f);
  const int nrm = w.add(std::vector<float>{r, 0, r, r, 0, r, r, 0, r}, 5126, "VEC3");
  w.meshes = fmt::format(R"([{{"primitives":[{{"attributes":{{"POSITION":{},"NORMAL":{}}}}}]}}])", pos, nrm);
  w.nodes = R"([{"scale":[2,1,1],"mesh":0}])";
  const Scene s = load_scene(w.write("gltf_scale", "scale.glb").string());
  // inverse transpose of diag(2,1,1) = diag(0.5,1,1): (r, 0, r) -> (0.5 r, 0, r), normalised.
  EXPECT_NEAR(s.normals[0].x, 0.5f / std::sqrt(1.25f), 1e-5f);
  EXPECT_NEAR(s.normals[0].z, 1.f / std::sqrt(1.25f), 1e-5f);
}

TEST(GltfLoader, StripsFansAndSkippedLines) {
  GltfWriter w;
  const int pos = w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 2, 0, 0});
  w.meshes = fmt::format(R"([{{"primitives":[{{"attributes":{{"POSITION":{0}}},"mode":5}},
                                            {{"attributes":{{"POSITION":{0}}},"mode":6}},
                                            {{"attributes":{{"POSITION":{0}}},"mode":1}},
                                            {{"attributes":{{"POSITION":{0}}},"mode":0}}]}}])",
                         pos);
  const Scene s = load_scene(w.write("gltf_modes", "modes.glb").string());
  EXPECT_EQ(s.triangle_count(), 3u + 3u);  // strip of 5 -> 3, fan of 5 -> 3; lines and points skipped
  expect_valid(s);
}

TEST(GltfLoader, MaterialsFromFactorsAndExtensions) {
  GltfWriter w;
  const int pos = w.positions(kTri);
  std::string prims;
  for (int m = 0; m < 6; ++m)
    prims += fmt::format("{}{{\"attributes\":{{\"POSITION\":{}}},\"material\":{}}}", m ? "," : "", pos, m);
  w.meshes = "[{\"primitives\":[" + prims + "]}]";
  w.materials = R"([
    {"name":"light","emissiveFactor":[1,0.5,0.25],
     "extensions":{"KHR_materials_emissive_strength":{"emissiveStrength":8}}},
    {"name":"glass",
     "extensions":{"KHR_materials_transmission":{"transmissionFactor":1},"KHR_materials_ior":{"ior":1.33}}},
    {"name":"solid",
     "extensions":{"KHR_materials_transmission":{"transmissionFactor":0.9},"KHR_materials_volume":{}}},
    {"name":"mirror",
     "pbrMetallicRoughness":{"baseColorFactor":[0.9,0.9,0.9,1],"metallicFactor":1,"roughnessFactor":0.01}},
    {"name":"textured",
     "pbrMetallicRoughness":{"baseColorTexture":{"index":0},"metallicFactor":0,"roughnessFactor":0.9}},
    {"name":"spec_default"}])";
  w.extra = R"(,"textures":[{"source":0}],"images":[{"uri":"missing.png"}])";
  const Scene s = load_scene(w.write("gltf_materials", "mat.glb").string());
  ASSERT_EQ(s.materials.size(), 6u);
  EXPECT_EQ(s.materials[0].cls, MaterialClass::Emissive);
  EXPECT_FLOAT_EQ(s.materials[0].emission.x, 8.f);
  EXPECT_FLOAT_EQ(s.materials[0].emission.z, 2.f);
  EXPECT_EQ(s.materials[1].cls, MaterialClass::Transmissive);
  EXPECT_TRUE(s.materials[1].thin_walled);
  EXPECT_FLOAT_EQ(s.materials[1].ior, 1.33f);
  EXPECT_FALSE(s.materials[2].thin_walled);
  EXPECT_EQ(s.materials[3].cls, MaterialClass::Specular);
  EXPECT_TRUE(s.materials[4].has_texture);
  EXPECT_EQ(s.materials[4].cls, MaterialClass::Diffuse);
  // glTF defaults: metallic 1, roughness 1 -> a rough metal, which is glossy.
  EXPECT_EQ(s.materials[5].cls, MaterialClass::Glossy);
  const SceneFeatures f = analyse(s);
  EXPECT_TRUE(f.has_textures);
  EXPECT_TRUE(f.has_emissive);
  EXPECT_EQ(s.emissive_tris.size(), 1u);
}

TEST(GltfLoader, CameraFromTrsNodeAndFallbackWithoutScenes) {
  GltfWriter w = one_triangle();
  w.cameras = R"([{"type":"orthographic","orthographic":{"xmag":1,"ymag":1,"zfar":10,"znear":0.1}},
                  {"type":"perspective","perspective":{"yfov":0.5,"znear":0.1}}])";
  // No scenes: every root node is drawn. The orthographic camera is ignored; the perspective one looks
  // down its -z, rotated 90 degrees about +y, i.e. towards -x.
  w.scenes.clear();
  w.nodes = R"([{"mesh":0},{"camera":0},{"camera":1,"translation":[5,1,0],"rotation":[0,0.70710678,0,0.70710678]}])";
  const Scene s = load_scene(w.write("gltf_camera", "cam.glb").string());
  EXPECT_TRUE(s.camera.from_file);
  EXPECT_NEAR(s.camera.eye.x, 5.f, 1e-6f);
  EXPECT_NEAR(s.camera.eye.y, 1.f, 1e-6f);
  const Vec3 d = normalize(s.camera.target - s.camera.eye);
  EXPECT_NEAR(d.x, -1.f, 1e-5f);
  EXPECT_NEAR(s.camera.vfov_deg, 0.5f * 180.f / 3.14159265f, 1e-3f);
}

TEST(GltfLoader, ZeroAreaTrianglesAreCountedAndKept) {
  GltfWriter w;
  const int pos = w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0});
  const int idx = w.u16({0, 1, 2, 0, 1, 3, 1, 1, 1});
  w.meshes = mesh_json(pos, idx);
  const Scene s = load_scene(w.write("gltf_degenerate", "deg.glb").string());
  EXPECT_EQ(s.triangle_count(), 3u);
  EXPECT_EQ(s.degenerate_tris, 2u);
  expect_valid(s);
}

// --- Synthetic glTF and OBJ: bad inputs -----------------------------------------------------------------------

TEST(BadInput, MissingEmptyRandomAndUnknownFiles) {
  const fs::path dir = test::temp_dir("bad_files");
  expect_load_error(dir / "no_such.glb", "no such file or built-in scene; built-ins: cornell, voxels");
  for (const char* name : {"empty.glb", "empty.gltf", "empty.obj"}) {
    test::write_file(dir / name, "");
    expect_load_error(dir / name, "empty");
  }
  std::string noise;
  uint32_t x = 12345;
  for (int i = 0; i < 4096; ++i) noise.push_back(static_cast<char>((x = x * 1664525u + 1013904223u) >> 24));
  for (const char* name : {"noise.glb", "noise.gltf"}) {
    test::write_file(dir / name, noise);
    expect_load_error(dir / name, "not a glTF file");
  }
  test::write_file(dir / "noise.obj", noise);
  expect_load_error(dir / "noise.obj");
  test::write_file(dir / "scene.txt", "hello");
  expect_load_error(dir / "scene.txt", "unknown file type");
  test::write_file(dir / "not_json.gltf", "{\"asset\": ");
  expect_load_error(dir / "not_json.gltf");
}

TEST(BadInput, TruncatedGlb) {
  const GltfWriter w = one_triangle();
  const std::string full = w.glb();
  const fs::path dir = test::temp_dir("bad_truncated");
  for (size_t keep : {size_t{10}, size_t{30}, full.size() / 2, full.size() - 4}) {
    const fs::path file = dir / fmt::format("cut{}.glb", keep);
    test::write_file(file, full.substr(0, keep));
    expect_load_error(file);
  }
}

TEST(BadInput, AccessorsOutsideTheirBuffers) {
  struct Case {
    const char* name;
    std::function<void(GltfWriter&)> spoil;
    const char* says;
  };
  const std::vector<Case> cases = {
      {"count.glb",
       [](GltfWriter& w) { w.accessors[0] = R"({"bufferView":0,"componentType":5126,"count":4,"type":"VEC3"})"; },
       "beyond"},
      {"offset.glb",
       [](GltfWriter& w) {
         w.accessors[0] = R"({"bufferView":0,"byteOffset":8,"componentType":5126,"count":3,"type":"VEC3"})";
       },
       "beyond"},
      {"stride.glb",
       [](GltfWriter& w) { w.views[0] = R"({"buffer":0,"byteOffset":0,"byteLength":36,"byteStride":16})"; }, "beyond"},
      {"view.glb", [](GltfWriter& w) { w.views[1] = R"({"buffer":0,"byteOffset":36,"byteLength":4000})"; },
       "outside buffer"},
      {"huge.glb",
       [](GltfWriter& w) {
         w.accessors[1] = R"({"bufferView":1,"componentType":5123,"count":4611686018427387904,"type":"SCALAR"})";
       },
       ""},
      {"no_view.glb",
       [](GltfWriter& w) { w.accessors[0] = R"({"bufferView":7,"componentType":5126,"count":3,"type":"VEC3"})"; },
       "buffer view"},
      {"bad_accessor.glb", [](GltfWriter& w) { w.meshes = mesh_json(0, 9); }, "accessor"},
      {"int_positions.glb",
       [](GltfWriter& w) { w.accessors[0] = R"({"bufferView":0,"componentType":5125,"count":3,"type":"VEC3"})"; },
       "float VEC3"},
      {"float_indices.glb",
       [](GltfWriter& w) { w.accessors[1] = R"({"bufferView":1,"componentType":5126,"count":1,"type":"SCALAR"})"; },
       "indices must be"},
      {"no_position.glb", [](GltfWriter& w) { w.meshes = R"([{"primitives":[{"attributes":{}}]}])"; }, "POSITION"},
      {"bad_mesh.glb", [](GltfWriter& w) { w.nodes = R"([{"mesh":3}])"; }, "mesh 3"},
      {"bad_node.glb", [](GltfWriter& w) { w.scenes = R"([{"nodes":[5]}])"; }, "node 5"},
      {"cycle.glb", [](GltfWriter& w) { w.nodes = R"([{"mesh":0,"children":[1]},{"children":[0]}])"; }, "twice"},
      {"bad_material.glb", [](GltfWriter& w) { w.meshes = mesh_json(0, 1, ",\"material\":4"); }, "material 4"},
  };
  for (const Case& c : cases) {
    GltfWriter w = one_triangle();
    c.spoil(w);
    expect_load_error(w.write("bad_accessors", c.name), c.says);
  }
}

TEST(BadInput, MissingOrUnloadableBuffers) {
  const GltfWriter w = one_triangle();
  const fs::path dir = test::temp_dir("bad_buffers");
  test::write_file(dir / "missing_bin.gltf", w.json("missing.bin"));
  expect_load_error(dir / "missing_bin.gltf");
  // A .gltf whose buffer has no uri and no GLB chunk to stand for.
  test::write_file(dir / "no_uri.gltf", w.json());
  expect_load_error(dir / "no_uri.gltf");
  // The external file is shorter than the declared byteLength.
  test::write_file(dir / "short.bin", w.bin.substr(0, 8));
  test::write_file(dir / "short_bin.gltf", w.json("short.bin"));
  expect_load_error(dir / "short_bin.gltf");
}

TEST(BadInput, IndicesOutOfRangeAndNonFinitePositions) {
  {
    GltfWriter w;
    const int pos = w.positions(kTri);
    w.meshes = mesh_json(pos, w.u16({0, 1, 3}));
    expect_load_error(w.write("bad_values", "index.glb"), "out of range");
  }
  for (float bad : {std::nanf(""), INFINITY, -INFINITY}) {
    GltfWriter w;
    const int pos = w.positions({0, 0, 0, 1, bad, 0, 0, 1, 0});
    w.meshes = mesh_json(pos, w.u16({0, 1, 2}));
    expect_load_error(
        w.write("bad_values", fmt::format("nonfinite_{}.glb", std::isnan(bad) ? "nan" : (bad > 0 ? "inf" : "ninf"))),
        "not finite");
  }
  {
    // A transform that overflows float turns finite input into infinity.
    GltfWriter w = one_triangle();
    w.nodes = R"([{"mesh":0,"scale":[1e39,1,1]}])";
    expect_load_error(w.write("bad_values", "overflow.glb"), "non-finite");
  }
}

TEST(BadInput, NoTrianglesToTrace) {
  {
    GltfWriter w;
    const int pos = w.positions(kTri);
    w.meshes = fmt::format(R"([{{"primitives":[{{"attributes":{{"POSITION":{}}},"mode":0}}]}}])", pos);
    expect_load_error(w.write("bad_empty", "points.glb"), "only point or line");
  }
  {
    GltfWriter w = one_triangle();
    w.nodes = R"([{"name":"empty"}])";
    expect_load_error(w.write("bad_empty", "nomesh.glb"), "no triangles");
  }
  {
    GltfWriter w;
    const int pos = w.positions(kTri);
    w.meshes = mesh_json(pos, w.u16({0, 1}));
    expect_load_error(w.write("bad_empty", "two_indices.glb"), "no triangles");
  }
}

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
  EXPECT_EQ(builtin_scene_names(), (std::vector<std::string>{"cornell", "voxels"}));
  EXPECT_NE(builtin_scene_summary("voxels").find("size=64 ([4, 1024])"), std::string::npos);
  EXPECT_FALSE(builtin_scene_summary("cornell").empty());
}

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

}  // namespace
}  // namespace raycoh

namespace raycoh {
namespace {

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
