// glTF 2.0 loader (.gltf and .glb): load_gltf reads the file, lets tinygltf (Debian 2.7, a shared library) parse
// it, decoding images to 8-bit RGBA through oiio/image_codec.h, refuses required extensions it cannot honour (one
// line naming the extension, Draco included) and hands the model to GltfReader. The scenes/gltf_*.cpp files are
// the only place that talks to tinygltf: node walking and the camera (gltf_nodes.cpp), accessors
// (gltf_accessors.cpp), meshes and primitives (gltf_meshes.cpp), materials (gltf_materials.cpp) and textures
// (gltf_textures.cpp), declared in gltf_reader.h.
//
// The whole node hierarchy of the default scene (or, without scenes, every root node) is flattened into world
// space: meshes are instanced once per node and once per EXT_mesh_gpu_instancing instance, normals go through the
// inverse transpose, and a mirroring transform flips the winding so geometric and shading normals stay on the same
// side. Triangle lists, strips and fans are read; points and lines are skipped and counted. Accessors may be
// sparse and, with KHR_mesh_quantization, byte or short; morph targets are applied with the default weights.
// Everything not traced as the file describes it (dropped primitives, skins, animations, extensions, tinygltf's
// warnings) becomes a line of Scene::load_notes, which `scenes info` prints.
//
// tinygltf 2.7 does not check that accessors fit their buffer views, that indices stay below the vertex count,
// or that node, mesh and material references are in range, so every reference and byte range is checked
// before it is read; any problem is a raycoh::Error naming the file.
//
// Materials: pbrMetallicRoughness factors, emissiveFactor x KHR_materials_emissive_strength,
// KHR_materials_transmission, KHR_materials_ior, KHR_materials_volume (present = solid, absent = thin-walled);
// textures scale them per triangle (gltf_textures.cpp). Camera: the first perspective camera met in the
// traversal, else the first orthographic one (ymag = half-height): eye at the node's origin, looking down its -Z.
// KHR_lights_punctual lights become Scene::lights.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "core/params.h"
#include "oiio/image_codec.h"
#include "scenes/gltf_reader.h"
#include "scenes/scene.h"

namespace raycoh {

namespace {

// Builds without OpenImageIO (RAYCOH_IMAGE_IO=OFF: the GPU bundle) decode with stb_image, which Debian's tinygltf
// links, to 8-bit RGBA (16-bit PNGs rounded to 8 bits). PNG is lossless, so its texels equal OIIO's; two JPEG
// decoders may differ by a level in some texels.
bool decode_with_stb(tinygltf::Image* image, int index, const unsigned char* bytes, int size, std::string& why) {
  if (!tinygltf::LoadImageData(image, index, &why, nullptr, 0, 0, bytes, size, nullptr)) return false;
  if (image->bits == 16) {
    std::vector<unsigned char> narrow(image->image.size() / 2);
    for (size_t i = 0; i < narrow.size(); ++i) {
      uint16_t v = 0;
      std::memcpy(&v, &image->image[2 * i], 2);
      narrow[i] = static_cast<unsigned char>((v * 255u + 32767u) / 65535u);
    }
    image->image = std::move(narrow);
    image->bits = 8;
    image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  }
  return image->component == 4 && image->bits == 8;
}

// Images are decoded to 8-bit RGBA (oiio/image_codec.h, OpenImageIO; stb_image in builds without it). One that cannot
// be decoded is a warning, not a failure: the materials using it keep their factors, and scenes info lists it.
// `model` is the one being loaded: tinygltf 2.7 hands a bufferView image to the loader without checking that the
// view lies inside its buffer (found by fuzz_gltf: a bufferView longer than its buffer, read past its end), so the
// loader checks it first and fails the load, naming the image, view and buffer.
bool decode_image(tinygltf::Image* image, const int index, std::string* err, std::string* warn, int, int,
                  const unsigned char* bytes, int size, void* model) {
  if (image->bufferView >= 0) {  // tinygltf has checked that the view and its buffer exist
    const auto& m = *static_cast<const tinygltf::Model*>(model);
    const tinygltf::BufferView& view = m.bufferViews[static_cast<size_t>(image->bufferView)];
    const size_t have = m.buffers[static_cast<size_t>(view.buffer)].data.size();
    if (view.byteOffset > have || view.byteLength > have - view.byteOffset || view.byteLength > INT32_MAX) {
      if (err)
        *err += fmt::format(
            "image {}: bufferView {} (byteOffset {}, byteLength {}) runs past the end of buffer {} "
            "({} bytes)\n",
            index, image->bufferView, view.byteOffset, view.byteLength, view.buffer, have);
      return false;
    }
  }
  Rgba8Image decoded;
  std::string why;
  if (size > 0 && !image_io_available()) {
    if (!decode_with_stb(image, index, bytes, size, why) && warn)
      *warn += fmt::format("image {} ({}) not decoded: {}\n", index, image->uri.empty() ? image->name : image->uri,
                           why.substr(0, why.find('\n')));
  } else if (size > 0 && decode_rgba8(bytes, static_cast<size_t>(size), decoded, why)) {
    image->width = decoded.width;
    image->height = decoded.height;
    image->component = 4;
    image->bits = 8;
    image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
    image->image = std::move(decoded.rgba);
  } else if (warn) {
    *warn += fmt::format("image {} ({}) not decoded: {}\n", index, image->uri.empty() ? image->name : image->uri,
                         size > 0 ? why : std::string("no data"));
  }
  return true;
}

// tinygltf messages span lines; an Error is one line.
std::string tinygltf_message(const std::string& text) {
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

// What the loader does with each glTF extension it knows. Supported: read as specified. Mapped: read
// approximately (the note says how). Any other extension is ignored when optional and refused when required.
struct ExtensionSupport {
  const char* name;
  bool mapped;       // false: supported
  const char* note;  // what is done with it
};
constexpr ExtensionSupport kExtensions[] = {
    {"KHR_materials_emissive_strength", false, "emission = emissiveFactor x emissiveStrength"},
    {"KHR_materials_transmission", false, "transmissionFactor decides transmissive (metal wins over transmission)"},
    {"KHR_materials_ior", false, "ior of transmissive materials"},
    {"KHR_materials_volume", false, "present = solid volume, absent = thin-walled; thickness and attenuation unused"},
    {"KHR_mesh_quantization", false, "byte and short attributes decoded to float"},
    {"EXT_mesh_gpu_instancing", false, "instances flattened into world-space triangles"},
    {"KHR_texture_transform", false, "offset, rotation, scale and texCoord of texture references"},
    {"KHR_lights_punctual", false,
     "point, spot and directional lights sampled by next-event estimation; candela and lux used as radiant "
     "intensity and irradiance; range honoured with the spec's window"},
    {"KHR_materials_clearcoat", true, "clear coat layer dropped: the base metallic-roughness lobe is traced"},
    {"KHR_materials_specular", true, "specular strength and colour dropped: the metallic-roughness lobe is traced"},
    {"KHR_materials_sheen", true, "sheen layer dropped: the base metallic-roughness lobe is traced"},
};

// Draco and the other compressions need a decoder this build does not have; naming the extension is the fix.
std::string why_unsupported(const std::string& name) {
  if (name == "KHR_draco_mesh_compression")
    return "Draco-compressed geometry cannot be decoded (no Draco library); use the uncompressed variant";
  if (name == "EXT_meshopt_compression") return "meshopt-compressed buffers cannot be decoded";
  if (name == "KHR_texture_basisu") return "Basis Universal textures cannot be decoded";
  if (name == "KHR_materials_variants") return "the default material of each primitive is used";
  if (name == "KHR_xmp" || name == "KHR_xmp_json_ld") return "metadata only";
  if (name == "KHR_materials_unlit") return "unlit materials are shaded as lit";
  return "raycoh does not support it";
}

// Refuses a required extension that is not supported (one line naming it) and notes every extension used.
void check_extensions(const std::string& path, const tinygltf::Model& model, std::vector<std::string>& notes) {
  auto known = [](const std::string& name) -> const ExtensionSupport* {
    for (const ExtensionSupport& e : kExtensions)
      if (name == e.name) return &e;
    return nullptr;
  };
  for (const std::string& name : model.extensionsRequired) {
    if (!known(name)) {
      std::vector<std::string> names;
      for (const ExtensionSupport& e : kExtensions) names.push_back(e.name);
      fail(path, fmt::format("requires glTF extension {}: {} (extensions read: {})", name, why_unsupported(name),
                             join(names)));
    }
  }
  std::vector<std::string> used = model.extensionsUsed;
  for (const std::string& name : model.extensionsRequired)
    if (std::find(used.begin(), used.end(), name) == used.end()) used.push_back(name);
  for (const std::string& name : used) {
    const ExtensionSupport* e = known(name);
    if (!e)
      notes.push_back(fmt::format("extension {}: ignored (optional; {})", name, why_unsupported(name)));
    else
      notes.push_back(fmt::format("extension {}: {} ({})", name, e->mapped ? "mapped" : "supported", e->note));
  }
}

// tinygltf's warnings, one note per line.
void note_warnings(const std::string& warn, std::vector<std::string>& notes) {
  size_t at = 0;
  while (at < warn.size()) {
    size_t end = warn.find('\n', at);
    if (end == std::string::npos) end = warn.size();
    std::string line = warn.substr(at, end - at);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (!line.empty()) notes.push_back("tinygltf warning: " + line);
    at = end + 1;
  }
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
tinygltf::Model parse_model(const std::string& path, const std::vector<unsigned char>& bytes,
                            std::vector<std::string>& notes) {
  tinygltf::TinyGLTF gltf;
  tinygltf::Model model;
  gltf.SetImageLoader(decode_image, &model);
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
    fail(path, fmt::format("not a valid glTF file: {}", tinygltf_message(e.what())));
  }
  // tinygltf also writes non-fatal notes (e.g. chunk padding) into err, so only the return value decides.
  if (!ok) {
    // tinygltf reads extensionsRequired before the accessors, so a Draco file is refused by name rather than for
    // the buffer views its compressed accessors lack.
    check_extensions(path, model, notes);
    // A buffer file that is not there is the user's most likely mistake; name it rather than blame the JSON.
    const std::string missing = "File not found : ";
    const size_t at = err.find(missing);
    if (at != std::string::npos) {
      const size_t from = at + missing.size();
      const size_t end = err.find_first_of("\r\n", from);
      fail(path, fmt::format("buffer file '{}' not found next to the scene",
                             err.substr(from, end == std::string::npos ? std::string::npos : end - from)));
    }
    fail(path, fmt::format("not a valid glTF {} file: {}", binary ? "binary" : "JSON", tinygltf_message(err)));
  }
  note_warnings(warn, notes);
  return model;
}

}  // namespace

Scene load_gltf(const std::string& path) {
  // The file's bytes are released once parsed, before the scene is built.
  Scene scene;
  const tinygltf::Model model = parse_model(path, read_bytes(path), scene.load_notes);
  check_extensions(path, model, scene.load_notes);
  scene.name = std::filesystem::path(path).stem().string();
  scene.source = path;
  gltf::GltfReader(model, path, scene).read();
  finalize_scene(scene);
  return scene;
}

std::vector<FileCamera> gltf_cameras(const std::string& path) {
  std::vector<std::string> notes;
  const tinygltf::Model model = parse_model(path, read_bytes(path), notes);
  Scene unused;
  return gltf::GltfReader(model, path, unused).cameras();
}

}  // namespace raycoh
