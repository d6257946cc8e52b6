// Internal to the glTF loader (scenes/gltf_*.cpp), which is the one adapter for tinygltf: no other part of the
// project includes this header or tiny_gltf.h. It holds the node transform (Mat4, column-major like glTF) and the
// matrix that maps normals, the checked view of one accessor's bytes, the material conversion, and GltfReader,
// which flattens a parsed tinygltf::Model into a Scene. GltfReader's members are spread by concern: node walking
// and the camera in gltf_nodes.cpp, accessor reading in gltf_accessors.cpp, meshes and primitives in
// gltf_meshes.cpp; load_gltf (file reading and parsing) is in gltf_loader.cpp.
#pragma once

#include <tiny_gltf.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "scenes/gltf_cameras.h"
#include "scenes/scene.h"

namespace raycoh::gltf {

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

// The node's matrix, or its translation * rotation * scale (gltf_nodes.cpp).
Mat4 local_transform(const tinygltf::Node& node);

// pbrMetallicRoughness factors and the supported extensions, classified (gltf_materials.cpp).
Material convert_material(const tinygltf::Material& gm, size_t index);

// A checked, strided view of one accessor's bytes.
struct AccessorView {
  const unsigned char* data = nullptr;
  size_t stride = 0;
  size_t count = 0;
  int component_type = 0;
  int type = 0;
  bool normalized = false;
};

// Flattens the default scene's node hierarchy of a parsed model into `scene`, checking every reference and byte
// range before it is read; a problem is a raycoh::Error naming `path`.
class GltfReader {
 public:
  GltfReader(const tinygltf::Model& model, const std::string& path, Scene& scene)
      : model_(model), path_(path), scene_(scene) {}

  void read();
  // Every camera node of the default scene, in traversal order (meshes are not read).
  std::vector<FileCamera> cameras() const;

 private:
  [[noreturn]] void fail(const std::string& what) const;
  void note_dropped();

  // gltf_nodes.cpp
  std::vector<int> root_nodes() const;
  void visit(int root, const Mat4& parent);
  void take_camera(const tinygltf::Node& node, const Mat4& world);
  void take_light(int index, const tinygltf::Node& node, const Mat4& world);
  // The view of camera node `node` at `world`; empty when usable, else why not.
  std::string camera_of(const tinygltf::Node& node, const Mat4& world, Camera& out) const;

  // gltf_accessors.cpp
  const unsigned char* bytes(int buffer_view, size_t offset, size_t stride, size_t count, size_t elem,
                             const std::string& name) const;
  AccessorView view(int index, const std::string& what, bool allow_sparse = false) const;
  std::vector<uint32_t> read_indices(int accessor, size_t vertex_count, const std::string& what) const;
  // Every element as floats (type: TINYGLTF_TYPE_VEC2/3/4): float, or byte/short (normalised or not, as
  // KHR_mesh_quantization allows), with sparse substitutions applied; non-finite values are errors.
  std::vector<float> read_floats(int accessor, int type, const std::string& what) const;
  void append_positions(const std::vector<float>& p, const Mat4& world);
  void append_normals(const tinygltf::Primitive& prim, const std::string& where, size_t base, size_t position_count,
                      const NormalMatrix& normal_matrix, const std::vector<double>& weights);
  void morph(const tinygltf::Primitive& prim, const char* attribute, const std::string& where,
             const std::vector<double>& weights, std::vector<float>& values);

  // gltf_textures.cpp
  void append_texcoords(const tinygltf::Primitive& prim, const std::string& where, size_t count);
  void apply_textures();
  // A kept triangle's per-hit material, corner texture coordinates and (normal-mapped) tangent, in
  // Scene::textures.
  void append_hit_uv(uint32_t hit_material, bool normal_mapped, const uint32_t* idx);
  // The unit tangent (dP/du of texture tex's coordinates) and bitangent sign of triangle idx into out[4]; left
  // as it is when the triangle has no UV frame.
  void triangle_tangent(const SurfaceTexture& tex, const uint32_t* idx, const float* corner_uv, float* out) const;
  // Scene::textures.tri_emission: each emissive-textured triangle's mean texel emission.
  void emitter_means();

  // gltf_meshes.cpp
  void read_mesh(int mesh_index, const Mat4& world, const std::vector<double>& node_weights);
  void read_instanced_mesh(int node_index, const tinygltf::Node& node, const Mat4& world);
  void read_primitive(const tinygltf::Primitive& prim, const std::string& where, const Mat4& world,
                      const NormalMatrix& normal_matrix, const std::vector<double>& weights);
  uint32_t primitive_material(const tinygltf::Primitive& prim, const std::string& where);
  std::vector<uint32_t> primitive_indices(const tinygltf::Primitive& prim, size_t vertex_count,
                                          const std::string& where) const;
  void emit_triangles(int mode, const std::vector<uint32_t>& idx, size_t base, uint32_t material, bool mirrored);
  uint32_t default_material();

  const tinygltf::Model& model_;
  const std::string& path_;
  Scene& scene_;
  std::vector<uint32_t> visit_count_;
  size_t skipped_points_ = 0, skipped_lines_ = 0;  // primitives not traced (no area)
  size_t morph_primitives_ = 0;                    // primitives with morph targets
  bool morph_weighted_ = false;                    // some morph target had a non-zero default weight
  size_t instanced_nodes_ = 0, instances_ = 0;     // EXT_mesh_gpu_instancing, flattened
  std::vector<float> uv_[2];                       // TEXCOORD_0 and _1 per scene vertex (zero where absent)
  int64_t default_material_ = -1;
  size_t dark_lights_ = 0;  // punctual lights with zero intensity, not traced
};

}  // namespace raycoh::gltf
