// glTF 2.0 loader (.gltf and .glb), the only place that talks to tinygltf (Debian 2.7, a shared library).
//
// The whole node hierarchy of the default scene (or, without scenes, every root node) is flattened into world
// space: meshes are instanced once per node, normals go through the inverse transpose, and a mirroring transform
// flips the winding so geometric and shading normals stay on the same side. Triangle lists, strips and fans are
// read; points and lines are skipped. Images are never decoded (no stage needs textures).
//
// tinygltf 2.7 does not check that accessors fit their buffer views, that indices stay below the vertex count,
// or that node, mesh and material references are in range, so every reference and byte range is checked here
// before it is read; any problem is a raycoh::Error naming the file.
//
// Materials: pbrMetallicRoughness factors, emissiveFactor x KHR_materials_emissive_strength,
// KHR_materials_transmission, KHR_materials_ior, KHR_materials_volume (present = solid, absent = thin-walled).
// Camera: the first perspective camera met in the traversal: eye at the node's origin, looking down its -Z.
#include <fmt/format.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "scenes/scene.h"

namespace raycoh {

namespace {

// Column-major like glTF: element (row r, column c) is m[4 * c + r].
struct Mat4 {
  double m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

  Mat4 operator*(const Mat4& b) const {
    Mat4 out;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) {
        double s = 0.0;
        for (int k = 0; k < 4; ++k) s += m[4 * k + r] * b.m[4 * c + k];
        out.m[4 * c + r] = s;
      }
    return out;
  }
  double at(int r, int c) const { return m[4 * c + r]; }
  Vec3 point(const float* p) const {
    return {static_cast<float>(at(0, 0) * p[0] + at(0, 1) * p[1] + at(0, 2) * p[2] + at(0, 3)),
            static_cast<float>(at(1, 0) * p[0] + at(1, 1) * p[1] + at(1, 2) * p[2] + at(1, 3)),
            static_cast<float>(at(2, 0) * p[0] + at(2, 1) * p[1] + at(2, 2) * p[2] + at(2, 3))};
  }
  Vec3 column(int c) const {
    return {static_cast<float>(at(0, c)), static_cast<float>(at(1, c)), static_cast<float>(at(2, c))};
  }
  double det3() const {
    return at(0, 0) * (at(1, 1) * at(2, 2) - at(1, 2) * at(2, 1)) -
           at(0, 1) * (at(1, 0) * at(2, 2) - at(1, 2) * at(2, 0)) +
           at(0, 2) * (at(1, 0) * at(2, 1) - at(1, 1) * at(2, 0));
  }
};

// The cofactor matrix of the upper 3x3 is det * inverse-transpose: it maps normals correctly (up to length and,
// for a negative determinant, sign) and stays defined for singular transforms.
struct NormalMatrix {
  double c[3][3];
  double sign = 1.0;
  explicit NormalMatrix(const Mat4& a) {
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col) {
        const int r1 = (r + 1) % 3, r2 = (r + 2) % 3, c1 = (col + 1) % 3, c2 = (col + 2) % 3;
        c[r][col] = a.at(r1, c1) * a.at(r2, c2) - a.at(r1, c2) * a.at(r2, c1);
      }
    sign = a.det3() < 0.0 ? -1.0 : 1.0;
  }
  Vec3 apply(const float* n) const {
    double o[3];
    for (int r = 0; r < 3; ++r) o[r] = sign * (c[r][0] * n[0] + c[r][1] * n[1] + c[r][2] * n[2]);
    const double len = std::sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]);
    // A zero result is kept as zero: finalize_scene replaces it by the face normal.
    if (!(len > 0.0) || !std::isfinite(len)) return {0.f, 0.f, 0.f};
    return {static_cast<float>(o[0] / len), static_cast<float>(o[1] / len), static_cast<float>(o[2] / len)};
  }
};

Mat4 local_transform(const tinygltf::Node& node) {
  Mat4 out;
  if (node.matrix.size() == 16) {
    for (int i = 0; i < 16; ++i) out.m[i] = node.matrix[i];
    return out;
  }
  Mat4 t, r, s;
  if (node.translation.size() == 3)
    for (int i = 0; i < 3; ++i) t.m[12 + i] = node.translation[i];
  if (node.rotation.size() == 4) {
    double x = node.rotation[0], y = node.rotation[1], z = node.rotation[2], w = node.rotation[3];
    const double len = std::sqrt(x * x + y * y + z * z + w * w);
    if (len > 0.0) {
      x /= len, y /= len, z /= len, w /= len;
    } else {
      x = y = z = 0.0, w = 1.0;
    }
    const double rm[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                             {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                             {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 3; ++col) r.m[4 * col + row] = rm[row][col];
  }
  if (node.scale.size() == 3)
    for (int i = 0; i < 3; ++i) s.m[5 * i] = node.scale[i];
  return t * r * s;
}

// Extension values are untyped JSON; Value::Get asserts on the wrong type, so every step is checked.
double number_in(const tinygltf::ExtensionMap& ext, const char* name, const char* key, double def) {
  const auto it = ext.find(name);
  if (it == ext.end() || !it->second.IsObject() || !it->second.Has(key)) return def;
  const tinygltf::Value& v = it->second.Get(key);
  return v.IsNumber() ? v.GetNumberAsDouble() : def;
}

bool texture_in(const tinygltf::ExtensionMap& ext, const char* name, const char* key) {
  const auto it = ext.find(name);
  return it != ext.end() && it->second.IsObject() && it->second.Has(key) && it->second.Get(key).IsObject();
}

Material convert_material(const tinygltf::Material& gm, size_t index) {
  Material m;
  m.name = gm.name.empty() ? fmt::format("material{}", index) : gm.name;
  const auto& pbr = gm.pbrMetallicRoughness;
  if (pbr.baseColorFactor.size() >= 3)
    m.base_color = {static_cast<float>(pbr.baseColorFactor[0]), static_cast<float>(pbr.baseColorFactor[1]),
                    static_cast<float>(pbr.baseColorFactor[2])};
  m.metallic = static_cast<float>(pbr.metallicFactor);
  m.roughness = static_cast<float>(pbr.roughnessFactor);
  const double strength = number_in(gm.extensions, "KHR_materials_emissive_strength", "emissiveStrength", 1.0);
  if (gm.emissiveFactor.size() >= 3)
    m.emission = {static_cast<float>(gm.emissiveFactor[0] * strength),
                  static_cast<float>(gm.emissiveFactor[1] * strength),
                  static_cast<float>(gm.emissiveFactor[2] * strength)};
  m.transmission =
      static_cast<float>(number_in(gm.extensions, "KHR_materials_transmission", "transmissionFactor", 0.0));
  m.ior = static_cast<float>(number_in(gm.extensions, "KHR_materials_ior", "ior", 1.5));
  m.thin_walled = gm.extensions.find("KHR_materials_volume") == gm.extensions.end();
  m.has_texture = pbr.baseColorTexture.index >= 0 || pbr.metallicRoughnessTexture.index >= 0 ||
                  gm.normalTexture.index >= 0 || gm.occlusionTexture.index >= 0 || gm.emissiveTexture.index >= 0 ||
                  texture_in(gm.extensions, "KHR_materials_transmission", "transmissionTexture");
  m.cls = classify_material(m);
  return m;
}

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

// A checked, strided view of one accessor's bytes.
struct AccessorView {
  const unsigned char* data = nullptr;
  size_t stride = 0;
  size_t count = 0;
  int component_type = 0;
  int type = 0;
};

class GltfReader {
 public:
  GltfReader(const tinygltf::Model& model, const std::string& path, Scene& scene)
      : model_(model), path_(path), scene_(scene) {}

  void read() {
    for (size_t i = 0; i < model_.materials.size(); ++i)
      scene_.materials.push_back(convert_material(model_.materials[i], i));
    visit_count_.assign(model_.nodes.size(), 0);
    for (int root : root_nodes()) visit(root, Mat4{});
    if (scene_.indices.empty()) {
      if (skipped_primitives_ > 0)
        fail(fmt::format("only point or line primitives ({} skipped); no triangles to trace", skipped_primitives_));
      fail("no triangles");
    }
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw Error(fmt::format("scene '{}': {}", path_, what)); }

  std::vector<int> root_nodes() const {
    if (!model_.scenes.empty()) {
      int s = model_.defaultScene;
      if (s < 0) s = 0;
      if (s >= static_cast<int>(model_.scenes.size()))
        fail(fmt::format("default scene {} does not exist ({} scenes)", s, model_.scenes.size()));
      return model_.scenes[static_cast<size_t>(s)].nodes;
    }
    std::vector<uint8_t> is_child(model_.nodes.size(), 0);
    for (const auto& node : model_.nodes)
      for (int c : node.children)
        if (c >= 0 && static_cast<size_t>(c) < is_child.size()) is_child[static_cast<size_t>(c)] = 1;
    std::vector<int> roots;
    for (size_t i = 0; i < model_.nodes.size(); ++i)
      if (!is_child[i]) roots.push_back(static_cast<int>(i));
    return roots;
  }

  // Depth-first with an explicit stack: a deep hierarchy cannot overflow the call stack, and a node reached twice
  // (a cycle, or a node shared by two parents, both invalid glTF) stops the load instead of looping.
  void visit(int root, const Mat4& parent) {
    std::vector<std::pair<int, Mat4>> stack{{root, parent}};
    while (!stack.empty()) {
      auto [index, parent_world] = stack.back();
      stack.pop_back();
      if (index < 0 || static_cast<size_t>(index) >= model_.nodes.size())
        fail(fmt::format("node {} does not exist ({} nodes)", index, model_.nodes.size()));
      if (visit_count_[static_cast<size_t>(index)]++ > 0)
        fail(fmt::format("node {} is reached twice; the node hierarchy must be a tree", index));
      const tinygltf::Node& node = model_.nodes[static_cast<size_t>(index)];
      const Mat4 world = parent_world * local_transform(node);
      if (node.mesh >= 0) {
        if (static_cast<size_t>(node.mesh) >= model_.meshes.size())
          fail(fmt::format("node {} refers to mesh {}, but there are {} meshes", index, node.mesh,
                           model_.meshes.size()));
        read_mesh(node.mesh, world);
      }
      if (node.camera >= 0) take_camera(node, world);
      // Reversed so that children are visited in file order (the first camera found is the first in the file).
      for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) stack.emplace_back(*it, world);
    }
  }

  void take_camera(const tinygltf::Node& node, const Mat4& world) {
    if (scene_.camera.from_file || static_cast<size_t>(node.camera) >= model_.cameras.size()) return;
    const tinygltf::Camera& cam = model_.cameras[static_cast<size_t>(node.camera)];
    if (cam.type != "perspective") return;
    const Vec3 forward = -world.column(2), up = world.column(1), eye = world.column(3);
    const double yfov = cam.perspective.yfov * 180.0 / 3.14159265358979323846;
    if (!is_finite(eye) || !is_finite(forward) || !is_finite(up) || !(dot(forward, forward) > 0.f) ||
        !(dot(up, up) > 0.f) || !(yfov > 0.0 && yfov < 180.0))
      return;
    // The target is one unit ahead: only the direction matters to the camera model.
    scene_.camera.eye = eye;
    scene_.camera.target = eye + normalize(forward);
    scene_.camera.up = normalize(up);
    scene_.camera.vfov_deg = static_cast<float>(yfov);
    scene_.camera.from_file = true;
  }

  AccessorView view(int index, const std::string& what) const {
    if (index < 0 || static_cast<size_t>(index) >= model_.accessors.size())
      fail(fmt::format("{} refers to accessor {}, but there are {} accessors", what, index, model_.accessors.size()));
    const tinygltf::Accessor& a = model_.accessors[static_cast<size_t>(index)];
    const std::string name = fmt::format("accessor {} ({})", index, what);
    if (a.sparse.isSparse) fail(name + " is sparse; sparse accessors are not supported");
    if (a.bufferView < 0 || static_cast<size_t>(a.bufferView) >= model_.bufferViews.size())
      fail(fmt::format("{} refers to buffer view {}, but there are {} buffer views", name, a.bufferView,
                       model_.bufferViews.size()));
    const tinygltf::BufferView& bv = model_.bufferViews[static_cast<size_t>(a.bufferView)];
    if (bv.buffer < 0 || static_cast<size_t>(bv.buffer) >= model_.buffers.size())
      fail(fmt::format("buffer view {} refers to buffer {}, but there are {} buffers", a.bufferView, bv.buffer,
                       model_.buffers.size()));
    const size_t buffer_size = model_.buffers[static_cast<size_t>(bv.buffer)].data.size();
    if (buffer_size == 0) fail(fmt::format("buffer {} is empty or could not be loaded", bv.buffer));
    const int comp = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(a.componentType));
    const int ncomp = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
    if (comp <= 0 || ncomp <= 0)
      fail(fmt::format("{} has an invalid component type {} or type {}", name, a.componentType, a.type));
    const size_t elem = static_cast<size_t>(comp) * static_cast<size_t>(ncomp);
    const size_t stride = bv.byteStride ? bv.byteStride : elem;
    if (stride < elem) fail(fmt::format("{}: byte stride {} is smaller than its {}-byte elements", name, stride, elem));
    if (bv.byteOffset > buffer_size || bv.byteLength > buffer_size - bv.byteOffset)
      fail(fmt::format("buffer view {} ({} bytes at offset {}) lies outside buffer {} ({} bytes)", a.bufferView,
                       bv.byteLength, bv.byteOffset, bv.buffer, buffer_size));
    AccessorView v;
    v.stride = stride;
    v.count = a.count;
    v.component_type = a.componentType;
    v.type = a.type;
    if (a.count == 0) return v;
    // 128-bit arithmetic: count and offsets come straight from JSON and may be absurd.
    const unsigned __int128 end =
        static_cast<unsigned __int128>(a.byteOffset) + static_cast<unsigned __int128>(stride) * (a.count - 1) + elem;
    if (end > bv.byteLength)
      fail(fmt::format(
          "{} needs {} elements of {} bytes at offset {} (stride {}), beyond the {} bytes of buffer view {}", name,
          a.count, elem, a.byteOffset, stride, bv.byteLength, a.bufferView));
    v.data = model_.buffers[static_cast<size_t>(bv.buffer)].data.data() + bv.byteOffset + a.byteOffset;
    return v;
  }

  std::vector<uint32_t> read_indices(int accessor, size_t vertex_count, const std::string& what) const {
    const AccessorView v = view(accessor, what);
    if (v.type != TINYGLTF_TYPE_SCALAR)
      fail(fmt::format("accessor {} ({}) must be SCALAR, not type {}", accessor, what, v.type));
    std::vector<uint32_t> out(v.count);
    for (size_t i = 0; i < v.count; ++i) {
      const unsigned char* p = v.data + i * v.stride;
      uint32_t value;
      switch (v.component_type) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
          value = p[0];
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
          uint16_t s;
          std::memcpy(&s, p, 2);
          value = s;
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
          std::memcpy(&value, p, 4);
          break;
        default:
          fail(fmt::format("accessor {} ({}) has component type {}; indices must be unsigned byte, short or int",
                           accessor, what, v.component_type));
      }
      if (value >= vertex_count)
        fail(fmt::format("accessor {} ({}): index {} at position {} is out of range ({} vertices)", accessor, what,
                         value, i, vertex_count));
      out[i] = value;
    }
    return out;
  }

  void check_float3(const AccessorView& v, int accessor, const std::string& what) const {
    if (v.type != TINYGLTF_TYPE_VEC3 || v.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT)
      fail(fmt::format("accessor {} ({}) must be float VEC3 (component type {}, type {} given)", accessor, what,
                       v.component_type, v.type));
  }

  void read_mesh(int mesh_index, const Mat4& world) {
    const tinygltf::Mesh& mesh = model_.meshes[static_cast<size_t>(mesh_index)];
    const NormalMatrix normal_matrix(world);
    const bool mirrored = normal_matrix.sign < 0.0;
    for (size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
      const tinygltf::Primitive& prim = mesh.primitives[pi];
      const std::string where = fmt::format("mesh {} primitive {}", mesh_index, pi);
      const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
      if (mode == TINYGLTF_MODE_POINTS || mode == TINYGLTF_MODE_LINE || mode == TINYGLTF_MODE_LINE_LOOP ||
          mode == TINYGLTF_MODE_LINE_STRIP) {
        ++skipped_primitives_;
        continue;
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

      uint32_t material;
      if (prim.material < 0) {
        material = default_material();
      } else if (static_cast<size_t>(prim.material) < model_.materials.size()) {
        material = static_cast<uint32_t>(prim.material);
      } else {
        fail(fmt::format("{} refers to material {}, but there are {} materials", where, prim.material,
                         model_.materials.size()));
      }

      std::vector<uint32_t> idx;
      if (prim.indices >= 0) {
        idx = read_indices(prim.indices, pv.count, "indices of " + where);
      } else {
        idx.resize(pv.count);
        for (size_t i = 0; i < pv.count; ++i) idx[i] = static_cast<uint32_t>(i);
      }

      for (size_t i = 0; i < pv.count; ++i) {
        float p[3];
        std::memcpy(p, pv.data + i * pv.stride, sizeof p);
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
          fail(fmt::format("accessor {} ({}): vertex {} is not finite ({}, {}, {})", pos_it->second, pos_what, i, p[0],
                           p[1], p[2]));
        scene_.positions.push_back(world.point(p));
      }

      const auto nrm_it = prim.attributes.find("NORMAL");
      if (nrm_it != prim.attributes.end()) {
        const std::string nrm_what = "NORMAL of " + where;
        const AccessorView nv = view(nrm_it->second, nrm_what);
        check_float3(nv, nrm_it->second, nrm_what);
        if (nv.count != pv.count) fail(fmt::format("{} has {} normals for {} positions", where, nv.count, pv.count));
        for (size_t i = 0; i < nv.count; ++i) {
          float n[3];
          std::memcpy(n, nv.data + i * nv.stride, sizeof n);
          scene_.normals.push_back(normal_matrix.apply(n));
        }
      } else {
        // Zero marks "generate": finalize_scene gives these vertices area-weighted normals.
        scene_.normals.resize(base + pv.count, Vec3{0.f, 0.f, 0.f});
        scene_.generated_normals = true;
      }

      auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
        if (mirrored) std::swap(b, c);
        scene_.indices.push_back(static_cast<uint32_t>(base) + a);
        scene_.indices.push_back(static_cast<uint32_t>(base) + b);
        scene_.indices.push_back(static_cast<uint32_t>(base) + c);
        scene_.tri_material.push_back(material);
      };
      // Strip and fan orders follow the glTF 2.0 specification (section 3.7.2.1), which keeps the winding.
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
  }

  uint32_t default_material() {
    if (default_material_ < 0) {
      default_material_ = static_cast<int64_t>(scene_.materials.size());
      scene_.materials.push_back(Material{"default"});
    }
    return static_cast<uint32_t>(default_material_);
  }

  const tinygltf::Model& model_;
  const std::string& path_;
  Scene& scene_;
  std::vector<uint32_t> visit_count_;
  size_t skipped_primitives_ = 0;
  int64_t default_material_ = -1;
};

}  // namespace

Scene load_gltf(const std::string& path) {
  auto fail = [&](const std::string& what) { throw Error(fmt::format("scene '{}': {}", path, what)); };
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("cannot open the file");
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) fail("cannot read the file");
  if (bytes.empty()) fail("the file is empty");
  if (bytes.size() > UINT32_MAX) fail("files over 4 GiB are not supported");

  tinygltf::TinyGLTF gltf;
  gltf.SetImageLoader(skip_image, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const std::string base_dir = std::filesystem::path(path).parent_path().string();
  // The content decides between binary and JSON, so a .glb holding JSON (or the reverse) still loads.
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  if (!binary) {
    const auto first = std::find_if(bytes.begin(), bytes.end(), [](unsigned char c) { return !std::isspace(c); });
    if (first == bytes.end() || *first != '{')
      fail("not a glTF file: it starts neither with the binary magic 'glTF' nor with a JSON object");
  }
  bool ok = false;
  // tinygltf reports most problems through err, but some malformed files make it throw (std::vector::at).
  try {
    ok = binary ? gltf.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), static_cast<unsigned>(bytes.size()),
                                            base_dir)
                : gltf.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                           static_cast<unsigned>(bytes.size()), base_dir);
  } catch (const std::exception& e) {
    fail(fmt::format("not a valid glTF file: {}", one_line(e.what())));
  }
  // tinygltf also writes non-fatal notes (e.g. chunk padding) into err, so only the return value decides.
  if (!ok) fail(fmt::format("not a valid glTF {} file: {}", binary ? "binary" : "JSON", one_line(err)));
  bytes = {};

  Scene scene;
  scene.name = std::filesystem::path(path).stem().string();
  scene.source = path;
  GltfReader(model, path, scene).read();
  finalize_scene(scene);
  return scene;
}

}  // namespace raycoh
