// Wavefront OBJ + MTL loader, the only place that talks to tinyobjloader (Debian 2.0rc10).
//
// Faces are fan-triangulated here rather than by tinyobjloader, because tinyobjloader silently drops polygons
// with out-of-range indices; every index is checked first, and a bad one is an Error naming the file. A fan
// also matches what the shared scenes' OBJ -> GLB converter did, so an OBJ and its GLB have the same triangles.
// Vertices are shared per material on (position, normal) pairs, as in that converter's GLB primitives.
// Corners without a `vn` get area-weighted normals (finalize_scene). A missing .mtl gives default materials.
//
// MTL -> material mapping, the same as the converter of ../shared/scenes (see its SOURCE.md files), so the OBJ
// and GLB of a scene classify the same:
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
#include <filesystem>
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

}  // namespace

Scene load_obj(const std::string& path) {
  auto fail = [&](const std::string& what) { throw Error(fmt::format("scene '{}': {}", path, what)); };
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) fail("no such file");
  if (std::filesystem::file_size(path, ec) == 0) fail("the file is empty");

  tinyobj::ObjReaderConfig config;
  config.triangulate = false;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  // Warnings (a missing .mtl, an unknown material name) are expected in the wild; defaults cover them.
  try {
    if (!reader.ParseFromFile(path, config)) fail(first_line(reader.Error()));
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    fail(first_line(e.what()));
  }

  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  const size_t vertex_count = attrib.vertices.size() / 3;
  const size_t normal_count = attrib.normals.size() / 3;

  Scene scene;
  scene.name = std::filesystem::path(path).stem().string();
  scene.source = path;
  for (const auto& mm : reader.GetMaterials()) scene.materials.push_back(convert_material(mm));
  const uint32_t file_materials = static_cast<uint32_t>(scene.materials.size());
  int64_t default_material = -1;

  // Key: (material, position index, normal index + 1); normal 0 means "none".
  struct Key {
    uint32_t material, v, vn;
    bool operator==(const Key& o) const { return material == o.material && v == o.v && vn == o.vn; }
  };
  struct KeyHash {
    size_t operator()(const Key& k) const {
      return std::hash<uint64_t>()((static_cast<uint64_t>(k.material) << 40) ^ (static_cast<uint64_t>(k.vn) << 20) ^
                                   k.v);
    }
  };
  std::unordered_map<Key, uint32_t, KeyHash> vertex_of;

  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const tinyobj::mesh_t& mesh = shape.mesh;
    size_t offset = 0;
    for (size_t f = 0; f < mesh.num_face_vertices.size(); ++f) {
      const size_t n = mesh.num_face_vertices[f];
      if (offset + n > mesh.indices.size())
        fail(fmt::format("object '{}': face {} is cut short (more than 255 corners?)", shape.name, f + 1));
      const int mat_id = f < mesh.material_ids.size() ? mesh.material_ids[f] : -1;
      uint32_t material;
      if (mat_id >= 0 && static_cast<uint32_t>(mat_id) < file_materials) {
        material = static_cast<uint32_t>(mat_id);
      } else {
        if (default_material < 0) {
          default_material = static_cast<int64_t>(scene.materials.size());
          scene.materials.push_back(Material{"default"});
        }
        material = static_cast<uint32_t>(default_material);
      }
      uint32_t corner[256];
      // Faces are numbered from 1 in each object, like lines in an editor, so that a user can find them.
      const std::string face =
          shape.name.empty() ? fmt::format("face {}", f + 1) : fmt::format("object '{}': face {}", shape.name, f + 1);
      for (size_t k = 0; k < n; ++k) {
        const tinyobj::index_t& ix = mesh.indices[offset + k];
        if (ix.vertex_index < 0)
          fail(fmt::format("{} refers to a vertex before the first one (relative index too large)", face));
        if (static_cast<size_t>(ix.vertex_index) >= vertex_count)
          fail(fmt::format("{} refers to vertex {}, but the file has {} vertices", face,
                           static_cast<int64_t>(ix.vertex_index) + 1, vertex_count));
        if (ix.normal_index < -1)
          fail(fmt::format("{} refers to a normal before the first one (relative index too large)", face));
        if (ix.normal_index >= 0 && static_cast<size_t>(ix.normal_index) >= normal_count)
          fail(fmt::format("{} refers to normal {}, but the file has {} normals", face,
                           static_cast<int64_t>(ix.normal_index) + 1, normal_count));
        const Key key{material, static_cast<uint32_t>(ix.vertex_index), static_cast<uint32_t>(ix.normal_index + 1)};
        auto [it, inserted] = vertex_of.try_emplace(key, static_cast<uint32_t>(scene.positions.size()));
        if (inserted) {
          if (scene.positions.size() >= UINT32_MAX) fail(fmt::format("more than {} vertices", UINT32_MAX));
          scene.positions.push_back(vec3(&attrib.vertices[3 * static_cast<size_t>(ix.vertex_index)]));
          if (ix.normal_index >= 0) {
            scene.normals.push_back(vec3(&attrib.normals[3 * static_cast<size_t>(ix.normal_index)]));
          } else {
            scene.normals.push_back(Vec3{0.f, 0.f, 0.f});  // zero = generate in finalize_scene
            scene.generated_normals = true;
          }
        }
        corner[k] = it->second;
      }
      for (size_t k = 1; k + 1 < n; ++k) {
        scene.indices.insert(scene.indices.end(), {corner[0], corner[k], corner[k + 1]});
        scene.tri_material.push_back(material);
      }
      offset += n;
    }
    if (offset != mesh.indices.size())
      fail(fmt::format("object '{}': face corner counts do not add up (a face with more than 255 corners?)",
                       shape.name));
  }
  if (scene.indices.empty()) fail("no triangles (no faces with three or more corners)");
  finalize_scene(scene);
  return scene;
}

}  // namespace raycoh
