// glTF 2.0 loader (.gltf and .glb): load_gltf reads the file, lets tinygltf (Debian 2.7, a shared library) parse
// it without decoding images, and hands the model to GltfReader. The scenes/gltf_*.cpp files are the only place
// that talks to tinygltf: node walking and the camera (gltf_nodes.cpp), accessors (gltf_accessors.cpp), meshes
// and primitives (gltf_meshes.cpp) and materials (gltf_materials.cpp), declared in gltf_reader.h.
//
// The whole node hierarchy of the default scene (or, without scenes, every root node) is flattened into world
// space: meshes are instanced once per node, normals go through the inverse transpose, and a mirroring transform
// flips the winding so geometric and shading normals stay on the same side. Triangle lists, strips and fans are
// read; points and lines are skipped. Images are never decoded (no stage needs textures).
//
// tinygltf 2.7 does not check that accessors fit their buffer views, that indices stay below the vertex count,
// or that node, mesh and material references are in range, so every reference and byte range is checked
// before it is read; any problem is a raycoh::Error naming the file.
//
// Materials: pbrMetallicRoughness factors, emissiveFactor x KHR_materials_emissive_strength,
// KHR_materials_transmission, KHR_materials_ior, KHR_materials_volume (present = solid, absent = thin-walled).
// Camera: the first perspective camera met in the traversal: eye at the node's origin, looking down its -Z.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "scenes/gltf_reader.h"
#include "scenes/scene.h"

namespace raycoh {

namespace {

bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

// tinygltf messages span lines; an Error is one line.
std::string one_line(const std::string& text) {
  std::string out;
  for (char ch : text) {
    if (ch == '\n' || ch == '\r') {
      if (!out.empty() && out.back() != ' ') out += "; ";
    } else {
      out += ch;
    }
  }
  while (!out.empty() && (out.back() == ' ' || out.back() == ';')) out.pop_back();
  // JSON parse errors quote the bytes read; a few hundred characters are enough to place the problem.
  if (out.size() > 300) out = out.substr(0, 300) + "...";
  return out.empty() ? std::string("unknown tinygltf error") : out;
}

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw Error(fmt::format("scene '{}': {}", path, what));
}

// The whole file, which must be non-empty and under 4 GiB.
std::vector<unsigned char> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the file");
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) fail(path, "cannot read the file");
  if (bytes.empty()) fail(path, "the file is empty");
  if (bytes.size() > UINT32_MAX) fail(path, "files over 4 GiB are not supported");
  return bytes;
}

// The content decides between binary and JSON, so a .glb holding JSON (or the reverse) still loads.
tinygltf::Model parse_model(const std::string& path, const std::vector<unsigned char>& bytes) {
  tinygltf::TinyGLTF gltf;
  gltf.SetImageLoader(skip_image, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const std::string base_dir = std::filesystem::path(path).parent_path().string();
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  if (!binary) {
    const auto first = std::find_if(bytes.begin(), bytes.end(), [](unsigned char c) { return !std::isspace(c); });
    if (first == bytes.end() || *first != '{')
      fail(path, "not a glTF file: it starts neither with the binary magic 'glTF' nor with a JSON object");
  }
  bool ok = false;
  // tinygltf reports most problems through err, but some malformed files make it throw (std::vector::at).
  try {
    ok = binary ? gltf.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), static_cast<unsigned>(bytes.size()),
                                            base_dir)
                : gltf.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                           static_cast<unsigned>(bytes.size()), base_dir);
  } catch (const std::exception& e) {
    fail(path, fmt::format("not a valid glTF file: {}", one_line(e.what())));
  }
  // tinygltf also writes non-fatal notes (e.g. chunk padding) into err, so only the return value decides.
  if (!ok) fail(path, fmt::format("not a valid glTF {} file: {}", binary ? "binary" : "JSON", one_line(err)));
  return model;
}

}  // namespace

Scene load_gltf(const std::string& path) {
  // The file's bytes are released once parsed, before the scene is built.
  const tinygltf::Model model = parse_model(path, read_bytes(path));
  Scene scene;
  scene.name = std::filesystem::path(path).stem().string();
  scene.source = path;
  gltf::GltfReader(model, path, scene).read();
  finalize_scene(scene);
  return scene;
}

}  // namespace raycoh
