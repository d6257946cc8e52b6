// The glTF loader on malformed input: missing, empty, random and truncated files, accessors outside their
// buffers, missing buffers, bad references and non-finite values, each of which must give one Error line that
// names the file (the good inputs are gltf_test.cpp's).
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
  expect_load_error(dir / "missing_bin.gltf", "buffer file 'missing.bin' not found");
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
  {
    // A cube far from the origin collapses in float: nothing could ever be hit.
    GltfWriter w = one_triangle();
    w.nodes = R"([{"mesh":0,"translation":[1e9,0,0],"scale":[1e-3,1e-3,1e-3]}])";
    expect_load_error(w.write("bad_empty", "collapsed.glb"), "zero area");
  }
}

// tinygltf 2.7 does not check that an image's bufferView lies inside its buffer; the loader does before decoding
// (fuzz_gltf found the texture read past the end of its buffer: tests/fuzz/regressions/gltf/).
TEST(BadInput, ImageBufferViewOutsideItsBuffer) {
  for (const char* view :
       {R"({"buffer":0,"byteOffset":0,"byteLength":100000})", R"({"buffer":0,"byteOffset":100000,"byteLength":4})"}) {
    GltfWriter w = one_triangle();
    w.views.push_back(view);
    w.extra = fmt::format(R"(,"images":[{{"bufferView":{},"mimeType":"image/png"}}])", w.views.size() - 1);
    expect_load_error(w.write("bad_image_view", "image.glb"),
                      fmt::format("image 0: bufferView {} (byteOffset", w.views.size() - 1));
  }
}

}  // namespace
}  // namespace raycoh
