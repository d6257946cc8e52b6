// Fuzz targets of the scene readers: glTF (with textures), OBJ + MTL, and scene specs with parameters.
#include <algorithm>
#include <cstdlib>
#include <string>

#include "core/params.h"
#include "scenes/scene.h"
#include "tests/fuzz/fuzz_targets.h"
#include "tests/fuzz/fuzz_util.h"

namespace raycoh::fuzz {

namespace {

// One triangle and two cameras (perspective "near", orthographic "top"): the file of the file:key=value specs.
constexpr const char* kCameraScene =
    R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,)"
    R"(AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],"bufferViews":[{"buffer":0,"byteLength":36}],)"
    R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],)"
    R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"cameras":[{"name":"near","type":"perspective",)"
    R"("perspective":{"yfov":0.8,"znear":0.01}},{"name":"top","type":"orthographic","orthographic":{"xmag":1,)"
    R"("ymag":1,"znear":0.01,"zfar":10}}],"nodes":[{"mesh":0},{"camera":0,"translation":[0.3,0.3,2]},)"
    R"({"camera":1,"translation":[0.3,0.3,3]}],"scenes":[{"nodes":[0,1,2]}],"scene":0})";

// The size parameters a built-in scene accepts go up to millions of triangles: valid, but seconds each. The fuzzer
// skips specs that ask for more than these (the parameter parser still sees every other spec); the values are the
// upper ends of what the parameters' ranges allow in a fraction of a second.
bool too_big(const std::string& spec) {
  for (const auto& [key, cap] : {std::pair<const char*, long>{"size=", 96}, {"tris=", 20000}}) {
    for (size_t at = spec.find(key); at != std::string::npos; at = spec.find(key, at + 1)) {
      const long v = std::strtol(spec.c_str() + at + std::string(key).size(), nullptr, 10);
      if (v > cap) return true;
    }
  }
  return false;
}

}  // namespace

void fuzz_gltf(const uint8_t* data, size_t size) {
  clear_scratch();
  const std::string path = write_scratch("scene.gltf", std::string(reinterpret_cast<const char*>(data), size));
  expect_clean("scene.gltf", [&] { load_gltf(path); });
}

// Input: the OBJ, then (after a split line, fuzz_util.h) the MTL it may name as "mtllib scene.mtl".
void fuzz_obj(const uint8_t* data, size_t size) {
  clear_scratch();
  const std::vector<std::string> parts = split_input(data, size, 2);
  const std::string path = write_scratch("scene.obj", parts[0]);
  if (parts.size() > 1) write_scratch("scene.mtl", parts[1]);
  expect_clean("scene.obj", [&] { load_obj(path); });
}

// First byte even: the rest is a spec of a built-in scene ("voxels:size=8"; other names are skipped, so that the
// fuzzer never names files of this machine). Odd: the rest are the parameters of a small glTF file with two
// cameras ("<file>:sun=1/2/3,camera=top").
void fuzz_scene_spec(const uint8_t* data, size_t size) {
  if (size < 1) return;
  const std::string rest(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (data[0] % 2 == 0) {
    const std::vector<std::string> builtins = builtin_scene_names();
    const std::string name = parse_plugin_spec(rest).name;
    if (std::find(builtins.begin(), builtins.end(), name) == builtins.end() || too_big(rest)) return;
    expect_clean("scene '" + name + "'", [&] { load_scene(rest); });
    return;
  }
  if (rest.find('\0') != std::string::npos) return;  // a C string on the command line cannot hold one
  clear_scratch();
  const std::string file = write_scratch("cameras.gltf", kCameraScene);
  expect_clean("cameras.gltf", [&] { load_scene(file + ":" + rest); });
}

}  // namespace raycoh::fuzz
