// glTF meshes and primitives: each primitive of a node's mesh is checked (mode, POSITION, material reference),
// its vertices are appended in world space and its triangle lists, strips and fans become triangles, with the
// winding flipped under a mirroring transform so geometric and shading normals stay on the same side; point and
// line primitives are counted and skipped, and primitives without a material share one "default" material.
// Part of the glTF loader, the one adapter for tinygltf.
#include <fmt/format.h>

#include <utility>

#include "scenes/gltf_reader.h"

namespace raycoh::gltf {

// Morph weights: the node's, else the mesh's default weights (glTF 2.0 section 3.7.2.2).
void GltfReader::read_mesh(int mesh_index, const Mat4& world, const std::vector<double>& node_weights) {
  const tinygltf::Mesh& mesh = model_.meshes[static_cast<size_t>(mesh_index)];
  const NormalMatrix normal_matrix(world);
  const std::vector<double>& weights = node_weights.empty() ? mesh.weights : node_weights;
  for (size_t pi = 0; pi < mesh.primitives.size(); ++pi)
    read_primitive(mesh.primitives[pi], fmt::format("mesh {} primitive {}", mesh_index, pi), world, normal_matrix,
                   weights);
}

// EXT_mesh_gpu_instancing, flattened: the mesh once per instance, at node world x T x R x S of the instance.
void GltfReader::read_instanced_mesh(int node_index, const tinygltf::Node& node, const Mat4& world) {
  const tinygltf::Value& ext = node.extensions.at("EXT_mesh_gpu_instancing");
  const std::string where = fmt::format("EXT_mesh_gpu_instancing of node {}", node_index);
  if (!ext.IsObject() || !ext.Has("attributes") || !ext.Get("attributes").IsObject())
    fail(where + " has no attributes object");
  const tinygltf::Value& attrs = ext.Get("attributes");
  std::vector<float> t, r, s;
  size_t count = 0;
  bool any = false;
  auto read = [&](const char* key, int type, std::vector<float>& out) {
    if (!attrs.Has(key)) return;
    const tinygltf::Value& v = attrs.Get(key);
    if (!v.IsInt()) fail(fmt::format("{}: {} is not an accessor index", where, key));
    out = read_floats(v.GetNumberAsInt(), type, fmt::format("{} of {}", key, where));
    const size_t n = out.size() / static_cast<size_t>(tinygltf::GetNumComponentsInType(static_cast<uint32_t>(type)));
    if (any && n != count) fail(fmt::format("{}: {} has {} instances, other attributes {}", where, key, n, count));
    count = n;
    any = true;
  };
  read("TRANSLATION", TINYGLTF_TYPE_VEC3, t);
  read("ROTATION", TINYGLTF_TYPE_VEC4, r);
  read("SCALE", TINYGLTF_TYPE_VEC3, s);
  if (!any) fail(where + " has none of TRANSLATION, ROTATION, SCALE");
  ++instanced_nodes_;
  instances_ += count;
  for (size_t i = 0; i < count; ++i) {
    tinygltf::Node trs;
    if (!t.empty()) trs.translation = {t[3 * i], t[3 * i + 1], t[3 * i + 2]};
    if (!r.empty()) trs.rotation = {r[4 * i], r[4 * i + 1], r[4 * i + 2], r[4 * i + 3]};
    if (!s.empty()) trs.scale = {s[3 * i], s[3 * i + 1], s[3 * i + 2]};
    read_mesh(node.mesh, world * local_transform(trs), node.weights);
  }
}

void GltfReader::read_primitive(const tinygltf::Primitive& prim, const std::string& where, const Mat4& world,
                                const NormalMatrix& normal_matrix, const std::vector<double>& weights) {
  const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
  if (mode == TINYGLTF_MODE_POINTS) {
    ++skipped_points_;
    return;
  }
  if (mode == TINYGLTF_MODE_LINE || mode == TINYGLTF_MODE_LINE_LOOP || mode == TINYGLTF_MODE_LINE_STRIP) {
    ++skipped_lines_;
    return;
  }
  if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN)
    fail(fmt::format("{} has unknown mode {}", where, mode));

  const auto pos_it = prim.attributes.find("POSITION");
  if (pos_it == prim.attributes.end()) fail(where + " has no POSITION attribute");
  std::vector<float> p = read_floats(pos_it->second, TINYGLTF_TYPE_VEC3, "POSITION of " + where);
  const size_t count = p.size() / 3;
  const size_t base = scene_.positions.size();
  if (count > UINT32_MAX - base) fail(fmt::format("more than {} vertices", UINT32_MAX));

  if (!prim.targets.empty()) ++morph_primitives_;
  const uint32_t material = primitive_material(prim, where);
  const std::vector<uint32_t> idx = primitive_indices(prim, count, where);
  morph(prim, "POSITION", where, weights, p);
  append_positions(p, world);
  append_normals(prim, where, base, count, normal_matrix, weights);
  append_texcoords(prim, where, count);
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
