// Wavefront OBJ + MTL loader, the only place that talks to tinyobjloader (Debian 2.0rc10).
//
// Faces are fan-triangulated here rather than by tinyobjloader, because tinyobjloader silently drops polygons
// with out-of-range indices; every index is checked first, and a bad one is an Error naming the file. A fan
// also matches what the shared scenes' OBJ -> GLB converter did, so an OBJ and its GLB have the same triangles.
// Vertices are shared per material on (position, normal) pairs, as in that converter's GLB primitives.
// Corners without a `vn` get area-weighted normals (finalize_scene). A missing .mtl gives default materials.
//
// MTL -> material mapping, the same as the converter that made the GLB test scenes from the McGuire archive's OBJ
// files (README.md, "Real scenes"), so the OBJ and GLB of a scene classify the same:
//   base colour   Kd; mirror-like materials (max Kd < 0.05, max Ks > 0.5) are metallic with base colour Ks;
//                 transmissive ones with Kd ~ 0 take Tf
//   roughness     1 when Ks = 0 (no highlight), else (2 / (Ns + 2))^(1/4): the Phong exponent's Beckmann
//                 alpha = sqrt(2 / (Ns + 2)), and glTF roughness = sqrt(alpha)
//   emission      Ke
//   transmission  1 - d when d < 1 (Tr = 1 - d), else 1 for the glass illumination models (illum 4, 6, 7, 9)
//   ior           Ni, or 1.5 when Ni <= 1 (many exporters write 1 for "unset")
//   thin-walled   glass illumination models are thin panes; dissolve-only transparency is a solid volume
#include <fmt/format.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "core/error.h"
#include "scenes/scene.h"

namespace raycoh {

namespace {

float max3(const tinyobj::real_t* v) { return std::max({v[0], v[1], v[2]}); }
Vec3 vec3(const tinyobj::real_t* v) { return {v[0], v[1], v[2]}; }

Material convert_material(const tinyobj::material_t& mm) {
  Material m;
  m.name = mm.name;
  const bool glass_model = mm.illum == 4 || mm.illum == 6 || mm.illum == 7 || mm.illum == 9;
  m.base_color = vec3(mm.diffuse);
  if (max3(mm.diffuse) < 0.05f && max3(mm.specular) > 0.5f) {
    m.metallic = 1.f;
    m.base_color = vec3(mm.specular);
  }
  m.roughness = max3(mm.specular) > 0.f ? std::pow(2.f / (std::max(mm.shininess, 0.f) + 2.f), 0.25f) : 1.f;
  m.emission = vec3(mm.emission);
  if (mm.dissolve < 1.f) {
    m.transmission = 1.f - std::max(mm.dissolve, 0.f);
  } else if (glass_model) {
    m.transmission = 1.f;
  }
  m.ior = mm.ior > 1.f ? mm.ior : 1.5f;
  m.thin_walled = glass_model || m.transmission == 0.f;
  if (m.transmission > 0.f && max3(mm.diffuse) < 0.05f) m.base_color = vec3(mm.transmittance);
  m.has_texture = !mm.diffuse_texname.empty() || !mm.specular_texname.empty() || !mm.bump_texname.empty() ||
                  !mm.alpha_texname.empty() || !mm.emissive_texname.empty() || !mm.normal_texname.empty() ||
                  !mm.roughness_texname.empty() || !mm.specular_highlight_texname.empty();
  m.cls = classify_material(m);
  return m;
}

std::string first_line(const std::string& text) {
  std::string out = text.substr(0, text.find('\n'));
  while (!out.empty() && (out.back() == '\r' || out.back() == ' ')) out.pop_back();
  return out.empty() ? std::string("unknown tinyobjloader error") : out;
}

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw Error(fmt::format("scene '{}': {}", path, what));
}

// tinyobjloader reads "v 1 zero 0" as (1, 0, 0) and "v 1 0" as (1, 0, 0) without a word, so every v, vn and vt
// line is checked first: each value a finite number (strtod must consume the whole token), and the count right
// (v: x y z, optionally w or r g b; vn: x y z; vt: u, optionally v and w).
void check_numbers(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  for (size_t number = 1; std::getline(in, line); ++number) {
    const size_t hash = line.find('#');
    std::istringstream tokens(line.substr(0, hash));
    std::string key;
    if (!(tokens >> key) || (key != "v" && key != "vn" && key != "vt")) continue;
    size_t count = 0;
    for (std::string tok; tokens >> tok; ++count) {
      char* end = nullptr;
      const double value = std::strtod(tok.c_str(), &end);
      if (end != tok.c_str() + tok.size() || !std::isfinite(value))
        fail(path, fmt::format("line {}: '{}' is not a finite number (in \"{}\")", number, tok, first_line(line)));
    }
    const size_t lo = key == "vt" ? 1 : 3, hi = key == "v" ? 6 : 3;
    if (count < lo || count > hi || (key == "v" && count == 5))
      fail(path, fmt::format("line {}: '{}' needs {} numbers, not {} (in \"{}\")", number, key,
                             key == "v" ? "3 (x y z), 4 (x y z w) or 6 (x y z r g b)"
                                        : (key == "vn" ? "3 (x y z)" : "1 to 3 (u v w)"),
                             count, first_line(line)));
  }
}

// Checks that the file exists and is not empty, then parses it (faces untriangulated).
void parse_obj(const std::string& path, tinyobj::ObjReader& reader) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) fail(path, "no such file");
  if (std::filesystem::file_size(path, ec) == 0) fail(path, "the file is empty");
  check_numbers(path);

  tinyobj::ObjReaderConfig config;
  config.triangulate = false;
  config.vertex_color = false;
  // Warnings (a missing .mtl, an unknown material name) are expected in the wild; defaults cover them.
  try {
    if (!reader.ParseFromFile(path, config)) fail(path, first_line(reader.Error()));
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    fail(path, first_line(e.what()));
  }
}

// Key: (material, position index, normal index + 1); normal 0 means "none".
struct VertexKey {
  uint32_t material, v, vn;
  bool operator==(const VertexKey& o) const { return material == o.material && v == o.v && vn == o.vn; }
};
struct VertexKeyHash {
  size_t operator()(const VertexKey& k) const {
    return std::hash<uint64_t>()((static_cast<uint64_t>(k.material) << 40) ^ (static_cast<uint64_t>(k.vn) << 20) ^ k.v);
  }
};

// Appends the faces of the parsed shapes to a scene whose file materials are already in place: every corner's
// indices are checked, vertices are shared per (material, position, normal), and each face becomes a fan.
class ObjMeshBuilder {
 public:
  ObjMeshBuilder(const std::string& path, const tinyobj::attrib_t& attrib, Scene& scene)
      : path_(path),
        attrib_(attrib),
        scene_(scene),
        vertex_count_(attrib.vertices.size() / 3),
        normal_count_(attrib.normals.size() / 3),
        file_materials_(static_cast<uint32_t>(scene.materials.size())) {}

  void add_shape(const tinyobj::shape_t& shape) {
    const tinyobj::mesh_t& mesh = shape.mesh;
    size_t offset = 0;
    for (size_t f = 0; f < mesh.num_face_vertices.size(); ++f) {
      const size_t n = mesh.num_face_vertices[f];
      if (offset + n > mesh.indices.size())
        fail(path_, fmt::format("object '{}': face {} is cut short (more than 255 corners?)", shape.name, f + 1));
      add_face(shape, f, offset, n);
      offset += n;
    }
    if (offset != mesh.indices.size())
      fail(path_, fmt::format("object '{}': face corner counts do not add up (a face with more than 255 corners?)",
                              shape.name));
  }

 private:
  void add_face(const tinyobj::shape_t& shape, size_t f, size_t offset, size_t n) {
    const tinyobj::mesh_t& mesh = shape.mesh;
    const uint32_t material = face_material(f < mesh.material_ids.size() ? mesh.material_ids[f] : -1);
    uint32_t corner[256];
    // Faces are numbered from 1 in each object, like lines in an editor, so that a user can find them.
    const std::string face =
        shape.name.empty() ? fmt::format("face {}", f + 1) : fmt::format("object '{}': face {}", shape.name, f + 1);
    for (size_t k = 0; k < n; ++k) corner[k] = corner_vertex(mesh.indices[offset + k], material, face);
    for (size_t k = 1; k + 1 < n; ++k) {
      scene_.indices.insert(scene_.indices.end(), {corner[0], corner[k], corner[k + 1]});
      scene_.tri_material.push_back(material);
    }
  }

  // The file's material, or one shared "default" material for faces without a (known) one.
  uint32_t face_material(int mat_id) {
    if (mat_id >= 0 && static_cast<uint32_t>(mat_id) < file_materials_) return static_cast<uint32_t>(mat_id);
    if (default_material_ < 0) {
      default_material_ = static_cast<int64_t>(scene_.materials.size());
      scene_.materials.push_back(Material{"default"});
    }
    return static_cast<uint32_t>(default_material_);
  }

  // The scene vertex of one face corner, added on first use.
  uint32_t corner_vertex(const tinyobj::index_t& ix, uint32_t material, const std::string& face) {
    if (ix.vertex_index < 0)
      fail(path_, fmt::format("{} refers to a vertex before the first one (relative index too large)", face));
    if (static_cast<size_t>(ix.vertex_index) >= vertex_count_)
      fail(path_, fmt::format("{} refers to vertex {}, but the file has {} vertices", face,
                              static_cast<int64_t>(ix.vertex_index) + 1, vertex_count_));
    if (ix.normal_index < -1)
      fail(path_, fmt::format("{} refers to a normal before the first one (relative index too large)", face));
    if (ix.normal_index >= 0 && static_cast<size_t>(ix.normal_index) >= normal_count_)
      fail(path_, fmt::format("{} refers to normal {}, but the file has {} normals", face,
                              static_cast<int64_t>(ix.normal_index) + 1, normal_count_));
    const VertexKey key{material, static_cast<uint32_t>(ix.vertex_index), static_cast<uint32_t>(ix.normal_index + 1)};
    auto [it, inserted] = vertex_of_.try_emplace(key, static_cast<uint32_t>(scene_.positions.size()));
    if (inserted) {
      if (scene_.positions.size() >= UINT32_MAX) fail(path_, fmt::format("more than {} vertices", UINT32_MAX));
      scene_.positions.push_back(vec3(&attrib_.vertices[3 * static_cast<size_t>(ix.vertex_index)]));
      if (ix.normal_index >= 0) {
        scene_.normals.push_back(vec3(&attrib_.normals[3 * static_cast<size_t>(ix.normal_index)]));
      } else {
        scene_.normals.push_back(Vec3{0.f, 0.f, 0.f});  // zero = generate in finalize_scene
        scene_.generated_normals = true;
      }
    }
    return it->second;
  }

  const std::string& path_;
  const tinyobj::attrib_t& attrib_;
  Scene& scene_;
  const size_t vertex_count_, normal_count_;
  const uint32_t file_materials_;
  int64_t default_material_ = -1;
  std::unordered_map<VertexKey, uint32_t, VertexKeyHash> vertex_of_;
};

}  // namespace

Scene load_obj(const std::string& path) {
  tinyobj::ObjReader reader;
  parse_obj(path, reader);
  Scene scene;
  scene.name = std::filesystem::path(path).stem().string();
  scene.source = path;
  for (const auto& mm : reader.GetMaterials()) scene.materials.push_back(convert_material(mm));
  ObjMeshBuilder builder(path, reader.GetAttrib(), scene);
  for (const tinyobj::shape_t& shape : reader.GetShapes()) builder.add_shape(shape);
  if (scene.indices.empty()) fail(path, "no triangles (no faces with three or more corners)");
  finalize_scene(scene);
  return scene;
}

}  // namespace raycoh
