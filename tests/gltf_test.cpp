// The glTF loader on synthetic files written by GltfWriter: index types, JSON with an external buffer, node
// hierarchies and their normals, strips and fans, materials and extensions, cameras (malformed input:
// gltf_bad_input_test.cpp).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "core/error.h"
#include "scenes/scene.h"
#include "tests/scenes_test_util.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

namespace fs = std::filesystem;

using test::expect_load_error;
using test::expect_valid;
using test::GltfWriter;
using test::kTri;
using test::mesh_json;
using test::one_triangle;

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
  // Nothing is dropped silently: scenes info lists both kinds.
  EXPECT_TRUE(test::has_note(s, "dropped 1 point primitive")) << join(s.load_notes, " | ");
  EXPECT_TRUE(test::has_note(s, "dropped 1 line primitive")) << join(s.load_notes, " | ");
}

TEST(GltfLoader, MorphDefaultWeightsSparseAccessorsAndInstancing) {
  GltfWriter w;
  const int pos = w.positions(kTri);
  const int idx = w.u16({0, 1, 2});
  const int offsets = w.positions({0, 0, 1, 0, 0, 1, 0, 0, 1});
  // Sparse: element 1 of a second position accessor replaced by (2, 0, 0).
  const int sparse_pos = w.positions(kTri);
  const int sparse_idx = w.u16({1});
  const int sparse_val = w.positions({2, 0, 0});
  w.accessors[static_cast<size_t>(sparse_pos)] = fmt::format(
      R"({{"bufferView":{},"componentType":5126,"count":3,"type":"VEC3","sparse":{{"count":1,
          "indices":{{"bufferView":{},"componentType":5123}},"values":{{"bufferView":{}}}}}}})",
      sparse_pos, sparse_idx, sparse_val);
  // Instances: translations (10, 0, 0) and (20, 0, 0).
  const int inst = w.positions({10, 0, 0, 20, 0, 0});
  w.meshes = fmt::format(R"([{{"primitives":[{{"attributes":{{"POSITION":{}}},"indices":{},
                                "targets":[{{"POSITION":{}}}]}}],"weights":[0.5]}},
                            {{"primitives":[{{"attributes":{{"POSITION":{}}},"indices":{}}}]}}])",
                         pos, idx, offsets, sparse_pos, idx);
  w.nodes = fmt::format(R"([{{"mesh":0}},{{"mesh":1,"translation":[0,5,0]}},
                            {{"mesh":1,"extensions":{{"EXT_mesh_gpu_instancing":{{"attributes":{{"TRANSLATION":{}}}}}}}}}])",
                        inst);
  w.scenes = R"([{"nodes":[0,1,2]}])";
  w.extra = R"(,"extensionsUsed":["EXT_mesh_gpu_instancing"])";
  const Scene s = load_scene(w.write("gltf_morph_sparse", "m.glb").string());
  ASSERT_EQ(s.triangle_count(), 1u + 1u + 2u);
  expect_valid(s);
  EXPECT_FLOAT_EQ(s.positions[0].z, 0.5f);  // base + 0.5 x target
  EXPECT_FLOAT_EQ(s.positions[4].x, 2.f);   // sparse substitution (mesh 1 at node 1)
  EXPECT_FLOAT_EQ(s.positions[4].y, 5.f);
  EXPECT_FLOAT_EQ(s.positions[7].x, 12.f);  // instance 1 of mesh 1: (2, 0, 0) + (10, 0, 0)
  EXPECT_FLOAT_EQ(s.positions[10].x, 22.f);
  EXPECT_TRUE(test::has_note(s, "EXT_mesh_gpu_instancing: 2 instance(s) on 1 node(s)")) << join(s.load_notes, " | ");
  EXPECT_TRUE(test::has_note(s, "default weights")) << join(s.load_notes, " | ");
}

// A 2 x 2 RGBA PNG: top row white, bottom row black.
const std::vector<uint8_t> kTwoRowPng = {
    137, 80,  78, 71, 13,  10,  26, 10,  0,  0,   0,  13,  73, 72, 68, 82, 0,   0,   0,  2,   0,   0,  0,  2,  8,
    6,   0,   0,  0,  114, 182, 13, 36,  0,  0,   0,  17,  73, 68, 65, 84, 120, 156, 99, 248, 15,  5,  12, 64, 0,
    34,  254, 3,  0,  113, 160, 9,  247, 61, 251, 21, 187, 0,  0,  0,  0,  73,  69,  78, 68,  174, 66, 96, 130};

TEST(GltfLoader, TexturesDecideMaterialsPerTriangle) {
  for (bool transform : {false, true}) {
    GltfWriter w;
    // Two triangles; every vertex of the first samples the top row (v = 0.25), of the second the bottom row.
    const int pos = w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 3, 0, 0, 2, 1, 0});
    const int uv =
        w.add(std::vector<float>{0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.75f, 0.25f, 0.75f, 0.25f, 0.75f},
              5126, "SCALAR");
    w.accessors[static_cast<size_t>(uv)] =
        fmt::format(R"({{"bufferView":{},"componentType":5126,"count":6,"type":"VEC2"}})", uv);
    const int png = w.add(kTwoRowPng, 5121, "SCALAR");
    w.meshes =
        fmt::format(R"([{{"primitives":[{{"attributes":{{"POSITION":{},"TEXCOORD_0":{}}},"material":0}}]}}])", pos, uv);
    // Emissive and metallic-roughness textures: white = lit, metal (blue 1) and rough (green 1); black = dark,
    // smooth dielectric. With KHR_texture_transform's offset [0, 0.5] and REPEAT the rows swap.
    const std::string ext = transform ? R"(,"extensions":{"KHR_texture_transform":{"offset":[0,0.5]}})" : std::string();
    w.materials = fmt::format(R"([{{"emissiveFactor":[2,2,2],"emissiveTexture":{{"index":0{0}}},
        "pbrMetallicRoughness":{{"metallicFactor":1,"roughnessFactor":1,"metallicRoughnessTexture":{{"index":0{0}}}}}}}])",
                              ext);
    w.extra = fmt::format(R"(,"textures":[{{"source":0}}],"images":[{{"bufferView":{},"mimeType":"image/png"}}])", png);
    const Scene s = load_scene(w.write("gltf_textures", fmt::format("t{}.glb", transform)).string());
    ASSERT_EQ(s.triangle_count(), 2u);
    expect_valid(s);
    const Material& lit = s.materials[s.tri_material[transform ? 1 : 0]];
    const Material& dark = s.materials[s.tri_material[transform ? 0 : 1]];
    EXPECT_EQ(lit.cls, MaterialClass::Emissive);
    EXPECT_FLOAT_EQ(lit.emission.x, 2.f);
    EXPECT_FLOAT_EQ(lit.metallic, 1.f);
    EXPECT_FLOAT_EQ(dark.emission.x, 0.f);
    EXPECT_FLOAT_EQ(dark.metallic, 0.f);
    EXPECT_FLOAT_EQ(dark.roughness, 0.f);
    EXPECT_EQ(dark.cls, MaterialClass::Specular);
    // Emitter sampling sees the textured emitter only.
    EXPECT_EQ(s.emissive_tris, std::vector<uint32_t>{transform ? 1u : 0u});
    EXPECT_TRUE(test::has_note(s, "textures: 2 triangle(s)")) << join(s.load_notes, " | ");
  }
}

TEST(GltfLoader, ExtensionsAreNotedAndUnsupportedRequiredOnesRefusedByName) {
  {
    GltfWriter w = one_triangle();
    w.extra = R"(,"extensionsUsed":["EXT_unknown_thing","KHR_materials_ior"])";
    const Scene s = load_scene(w.write("gltf_ext", "optional.glb").string());
    EXPECT_TRUE(test::has_note(s, "extension EXT_unknown_thing: ignored")) << join(s.load_notes, " | ");
    EXPECT_TRUE(test::has_note(s, "extension KHR_materials_ior: supported")) << join(s.load_notes, " | ");
  }
  for (const char* ext : {"EXT_unknown_thing", "KHR_draco_mesh_compression"}) {
    GltfWriter w = one_triangle();
    w.extra = fmt::format(R"(,"extensionsUsed":["{0}"],"extensionsRequired":["{0}"])", ext);
    expect_load_error(w.write("gltf_ext", fmt::format("required_{}.glb", ext)), std::string("extension ") + ext);
  }
  GltfWriter w = one_triangle();
  w.extra = R"(,"extensionsUsed":["KHR_draco_mesh_compression"],"extensionsRequired":["KHR_draco_mesh_compression"])";
  expect_load_error(w.write("gltf_ext", "draco.glb"), "Draco");
}

TEST(GltfLoader, MetalWinsOverTransmission) {
  GltfWriter w = one_triangle();
  w.meshes = mesh_json(0, 1, ",\"material\":0");
  w.materials = R"([{"pbrMetallicRoughness":{"metallicFactor":1,"roughnessFactor":0.3},
                     "extensions":{"KHR_materials_transmission":{"transmissionFactor":1}}}])";
  const Scene s = load_scene(w.write("gltf_metal_transmission", "m.glb").string());
  EXPECT_EQ(s.materials[0].cls, MaterialClass::Glossy);
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
    {"name":"glass","pbrMetallicRoughness":{"metallicFactor":0},
     "extensions":{"KHR_materials_transmission":{"transmissionFactor":1},"KHR_materials_ior":{"ior":1.33}}},
    {"name":"solid","pbrMetallicRoughness":{"metallicFactor":0},
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
  // No scenes: every root node is drawn. The perspective camera is preferred to the orthographic one met
  // first; it looks down its -z, rotated 90 degrees about +y, i.e. towards -x.
  w.scenes.clear();
  w.nodes = R"([{"mesh":0},{"camera":0},{"camera":1,"translation":[5,1,0],"rotation":[0,0.70710678,0,0.70710678]}])";
  const Scene s = load_scene(w.write("gltf_camera", "cam.glb").string());
  EXPECT_TRUE(s.camera.from_file);
  EXPECT_NEAR(s.camera.eye.x, 5.f, 1e-6f);
  EXPECT_NEAR(s.camera.eye.y, 1.f, 1e-6f);
  const Vec3 d = normalize(s.camera.target - s.camera.eye);
  EXPECT_NEAR(d.x, -1.f, 1e-5f);
  EXPECT_NEAR(s.camera.vfov_deg, 0.5f * 180.f / 3.14159265f, 1e-3f);
  EXPECT_EQ(s.camera.ortho_half_height, 0.f);
  // Only an orthographic camera: it is used.
  w.nodes = R"([{"mesh":0},{"camera":0,"translation":[0,0,3]}])";
  const Scene o = load_scene(w.write("gltf_camera", "ortho.glb").string());
  EXPECT_TRUE(o.camera.from_file);
  EXPECT_EQ(o.camera.ortho_half_height, 1.f);
  EXPECT_TRUE(test::has_note(o, "the first (orthographic) camera in the scene is used")) << join(o.load_notes, " | ");
}

TEST(GltfLoader, CameraParameterPicksACameraByIndexOrName) {
  GltfWriter w = one_triangle();
  w.cameras = R"([{"type":"orthographic","orthographic":{"xmag":1,"ymag":1,"zfar":10,"znear":0.1}},
                  {"type":"perspective","perspective":{"yfov":0.5,"znear":0.1}}])";
  w.nodes = R"([{"mesh":0,"children":[1,2,3]},{"camera":0,"name":"ortho"},{"camera":1,"translation":[5,1,0]},
                {"camera":1,"name":"side","translation":[0,0,7]}])";
  const std::string file = w.write("gltf_camera_pick", "cams.glb").string();
  EXPECT_NEAR(load_scene(file).camera.eye.x, 5.f, 1e-6f);  // the first usable camera by default
  EXPECT_NEAR(load_scene(file + ":camera=2").camera.eye.z, 7.f, 1e-6f);
  EXPECT_NEAR(load_scene(file + ":camera=side").camera.eye.z, 7.f, 1e-6f);
  EXPECT_NEAR(load_scene(file + ":camera=camera1").camera.eye.x, 5.f, 1e-6f);
  const Scene ortho = load_scene(file + ":camera=ortho");
  EXPECT_EQ(ortho.camera.ortho_half_height, 1.f);
  EXPECT_NEAR(ortho.camera.eye.x, 0.f, 1e-6f);
  const std::string bad = test::error_of([&] { load_scene(file + ":camera=9"); });
  EXPECT_NE(bad.find("0, 1, 2, ortho, camera1, side"), std::string::npos) << bad;
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

}  // namespace
}  // namespace raycoh
