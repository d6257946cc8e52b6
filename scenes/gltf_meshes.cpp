// glTF meshes and primitives: each primitive of a node's mesh is checked (mode, POSITION, material reference),
// its vertices are appended in world space and its triangle lists, strips and fans become triangles, with the
// winding flipped under a mirroring transform so geometric and shading normals stay on the same side; point and
// line primitives are counted and skipped, and primitives without a material share one "default" material.
// Part of the glTF loader, the one adapter for tinygltf.
#include <fmt/format.h>

#include <utility>

#include "scenes/gltf_reader.h"

namespace raycoh::gltf {

void GltfReader::read_mesh(int mesh_index, const Mat4& world) {
  const tinygltf::Mesh& mesh = model_.meshes[static_cast<size_t>(mesh_index)];
  const NormalMatrix normal_matrix(world);
  for (size_t pi = 0; pi < mesh.primitives.size(); ++pi)
    read_primitive(mesh.primitives[pi], fmt::format("mesh {} primitive {}", mesh_index, pi), world, normal_matrix);
}

void GltfReader::read_primitive(const tinygltf::Primitive& prim, const std::string& where, const Mat4& world,
                                const NormalMatrix& normal_matrix) {
  const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
  if (mode == TINYGLTF_MODE_POINTS || mode == TINYGLTF_MODE_LINE || mode == TINYGLTF_MODE_LINE_LOOP ||
      mode == TINYGLTF_MODE_LINE_STRIP) {
    ++skipped_primitives_;
    return;
  }
  if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN)
    fail(fmt::format("{} has unknown mode {}", where, mode));

  const auto pos_it = prim.attributes.find("POSITION");
  if (pos_it == prim.attributes.end()) fail(where + " has no POSITION attribute");
  const std::string pos_what = "POSITION of " + where;
  const AccessorView pv = view(pos_it->second, pos_what);
  check_float3(pv, pos_it->second, pos_what);
  const size_t base = scene_.positions.size();
  if (pv.count > UINT32_MAX - base) fail(fmt::format("more than {} vertices", UINT32_MAX));

  const uint32_t material = primitive_material(prim, where);
  const std::vector<uint32_t> idx = primitive_indices(prim, pv.count, where);
  append_positions(pv, pos_it->second, pos_what, world);
  append_normals(prim, where, base, pv.count, normal_matrix);
  emit_triangles(mode, idx, base, material, normal_matrix.sign < 0.0);
}

uint32_t GltfReader::primitive_material(const tinygltf::Primitive& prim, const std::string& where) {
  if (prim.material < 0) return default_material();
  if (static_cast<size_t>(prim.material) >= model_.materials.size())
    fail(fmt::format("{} refers to material {}, but there are {} materials", where, prim.material,
                     model_.materials.size()));
  return static_cast<uint32_t>(prim.material);
}

// The index accessor, or 0, 1, ..., n - 1 for a non-indexed primitive.
std::vector<uint32_t> GltfReader::primitive_indices(const tinygltf::Primitive& prim, size_t vertex_count,
                                                    const std::string& where) const {
  if (prim.indices >= 0) return read_indices(prim.indices, vertex_count, "indices of " + where);
  std::vector<uint32_t> idx(vertex_count);
  for (size_t i = 0; i < vertex_count; ++i) idx[i] = static_cast<uint32_t>(i);
  return idx;
}

// Strip and fan orders follow the glTF 2.0 specification (section 3.7.2.1), which keeps the winding.
void GltfReader::emit_triangles(int mode, const std::vector<uint32_t>& idx, size_t base, uint32_t material,
                                bool mirrored) {
  auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
    if (mirrored) std::swap(b, c);
    scene_.indices.push_back(static_cast<uint32_t>(base) + a);
    scene_.indices.push_back(static_cast<uint32_t>(base) + b);
    scene_.indices.push_back(static_cast<uint32_t>(base) + c);
    scene_.tri_material.push_back(material);
  };
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    for (size_t i = 0; i + 2 < idx.size(); i += 3) emit(idx[i], idx[i + 1], idx[i + 2]);
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (size_t i = 0; i + 2 < idx.size(); ++i) {
      if (i % 2 == 0)
        emit(idx[i], idx[i + 1], idx[i + 2]);
      else
        emit(idx[i], idx[i + 2], idx[i + 1]);
    }
  } else {
    for (size_t i = 1; i + 1 < idx.size(); ++i) emit(idx[i], idx[i + 1], idx[0]);
  }
}

uint32_t GltfReader::default_material() {
  if (default_material_ < 0) {
    default_material_ = static_cast<int64_t>(scene_.materials.size());
    scene_.materials.push_back(Material{"default"});
  }
  return static_cast<uint32_t>(default_material_);
}

}  // namespace raycoh::gltf
