// glTF node walking: GltfReader::read picks the root nodes of the default scene (or, without scenes, every node
// that is nobody's child), walks the hierarchy depth-first composing node transforms into world space, reads
// each node's mesh, takes the first perspective camera met (else the first orthographic one; eye at the node's
// origin, looking down its -Z) and
// every KHR_lights_punctual light a node refers to (at the node's origin, shining down its -Z; node scale does
// not change a light).
// Also the node's local transform (matrix, or translation * rotation * scale). Part of the glTF loader, the one
// adapter for tinygltf.
#include <fmt/format.h>

#include <cmath>
#include <utility>

#include "core/error.h"
#include "scenes/gltf_reader.h"

namespace raycoh::gltf {

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

void GltfReader::read() {
  for (size_t i = 0; i < model_.materials.size(); ++i)
    scene_.materials.push_back(convert_material(model_.materials[i], i));
  visit_count_.assign(model_.nodes.size(), 0);
  for (int root : root_nodes()) visit(root, Mat4{});
  const size_t skipped = skipped_points_ + skipped_lines_;
  if (scene_.indices.empty()) {
    if (skipped > 0) fail(fmt::format("only point or line primitives ({} skipped); no triangles to trace", skipped));
    fail("no triangles");
  }
  apply_textures();
  note_dropped();
}

// Everything in the file that is not traced as it would animate or render, so that nothing is dropped silently.
void GltfReader::note_dropped() {
  auto& notes = scene_.load_notes;
  if (skipped_points_ > 0)
    notes.push_back(fmt::format("dropped {} point primitive(s): points have no area to trace", skipped_points_));
  if (skipped_lines_ > 0)
    notes.push_back(fmt::format("dropped {} line primitive(s): lines have no area to trace", skipped_lines_));
  if (instances_ > 0)
    notes.push_back(fmt::format("EXT_mesh_gpu_instancing: {} instance(s) on {} node(s), flattened into world space",
                                instances_, instanced_nodes_));
  if (morph_primitives_ > 0)
    notes.push_back(fmt::format("{} primitive(s) with morph targets: base shape{}", morph_primitives_,
                                morph_weighted_ ? " plus the mesh's default weights" : " (default weights 0)"));
  if (!scene_.lights.empty() || dark_lights_ > 0) {
    size_t by_type[3] = {0, 0, 0};
    for (const PunctualLight& l : scene_.lights) ++by_type[static_cast<int>(l.type)];
    notes.push_back(fmt::format(
        "KHR_lights_punctual: {} light(s) traced ({} point, {} spot, {} directional), sampled by next-event "
        "estimation{}",
        scene_.lights.size(), by_type[0], by_type[1], by_type[2],
        dark_lights_ > 0 ? fmt::format("; {} with zero intensity dropped", dark_lights_) : std::string()));
  }
  if (!model_.skins.empty())
    notes.push_back(fmt::format("{} skin(s): meshes at their node transforms (rest pose), joints not applied",
                                model_.skins.size()));
  if (!model_.animations.empty())
    notes.push_back(fmt::format("{} animation(s) ignored: the static pose is traced", model_.animations.size()));
  if (model_.scenes.size() > 1)
    notes.push_back(fmt::format("{} scenes in the file: the default scene is traced", model_.scenes.size()));
  size_t ortho = 0;
  for (const auto& c : model_.cameras) ortho += c.type == "orthographic";
  const char* used = !scene_.camera.from_file                 ? "none used, default framing"
                     : scene_.camera.ortho_half_height == 0.f ? "the first perspective camera in the scene is used"
                                                              : "the first (orthographic) camera in the scene is used";
  if (!model_.cameras.empty())
    notes.push_back(fmt::format("{} camera(s) in the file{}: {}", model_.cameras.size(),
                                ortho ? fmt::format(" ({} orthographic)", ortho) : std::string(), used));
}

void GltfReader::fail(const std::string& what) const { throw Error(fmt::format("scene '{}': {}", path_, what)); }

std::vector<int> GltfReader::root_nodes() const {
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
void GltfReader::visit(int root, const Mat4& parent) {
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
        fail(fmt::format("node {} refers to mesh {}, but there are {} meshes", index, node.mesh, model_.meshes.size()));
      if (node.extensions.count("EXT_mesh_gpu_instancing"))
        read_instanced_mesh(index, node, world);
      else
        read_mesh(node.mesh, world, node.weights);
    }
    if (node.camera >= 0) take_camera(node, world);
    if (node.extensions.count("KHR_lights_punctual")) take_light(index, node, world);
    // Reversed so that children are visited in file order (the first camera found is the first in the file).
    for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) stack.emplace_back(*it, world);
  }
}

void GltfReader::take_light(int index, const tinygltf::Node& node, const Mat4& world) {
  const tinygltf::Value& ext = node.extensions.at("KHR_lights_punctual");
  if (!ext.IsObject() || !ext.Has("light") || !ext.Get("light").IsInt())
    fail(fmt::format("node {}: KHR_lights_punctual needs an integer 'light'", index));
  const int li = ext.Get("light").GetNumberAsInt();
  if (li < 0 || static_cast<size_t>(li) >= model_.lights.size())
    fail(fmt::format("node {} refers to light {}, but there are {} lights", index, li, model_.lights.size()));
  const tinygltf::Light& gl = model_.lights[static_cast<size_t>(li)];
  PunctualLight l;
  l.name = gl.name.empty() ? fmt::format("light{}", li) : gl.name;
  const std::string who = fmt::format("light {} '{}'", li, l.name);
  if (gl.type == "point") {
    l.type = LightType::Point;
  } else if (gl.type == "spot") {
    l.type = LightType::Spot;
  } else if (gl.type == "directional") {
    l.type = LightType::Directional;
  } else {
    fail(fmt::format("{} has type '{}'; valid: point, spot, directional", who, gl.type));
  }
  Vec3 colour{1.f, 1.f, 1.f};
  if (!gl.color.empty()) {
    if (gl.color.size() != 3) fail(fmt::format("{} has {} colour components, not 3", who, gl.color.size()));
    colour = {static_cast<float>(gl.color[0]), static_cast<float>(gl.color[1]), static_cast<float>(gl.color[2])};
  }
  l.intensity = colour * static_cast<float>(gl.intensity);
  l.position = world.column(3);
  const Vec3 forward = -world.column(2);
  l.direction = dot(forward, forward) > 0.f ? normalize(forward) : forward;  // zero: finalize_scene refuses it
  if (l.type != LightType::Directional) l.range = static_cast<float>(gl.range);
  if (l.type == LightType::Spot) {
    const double inner = gl.spot.innerConeAngle, outer = gl.spot.outerConeAngle;
    if (!(inner >= 0.0 && inner <= outer && outer <= 0.5 * 3.14159265358979323846 + 1e-6))
      fail(fmt::format("{}: spot cone angles inner {} and outer {} must satisfy 0 <= inner <= outer <= pi/2", who,
                       inner, outer));
    l.cos_inner = static_cast<float>(std::cos(inner));
    l.cos_outer = static_cast<float>(std::cos(outer));
  }
  if (!(max_component(l.intensity) > 0.f)) {
    ++dark_lights_;
    return;
  }
  scene_.lights.push_back(l);
}

// The first perspective camera, else the first orthographic one.
void GltfReader::take_camera(const tinygltf::Node& node, const Mat4& world) {
  const bool have = scene_.camera.from_file;
  if (have && scene_.camera.ortho_half_height == 0.f) return;
  Camera cam;
  if (!camera_of(node, world, cam).empty()) return;
  if (!have || cam.ortho_half_height == 0.f) scene_.camera = cam;
}

std::string GltfReader::camera_of(const tinygltf::Node& node, const Mat4& world, Camera& out) const {
  if (node.camera < 0 || static_cast<size_t>(node.camera) >= model_.cameras.size())
    return fmt::format("camera {} does not exist", node.camera);
  const tinygltf::Camera& cam = model_.cameras[static_cast<size_t>(node.camera)];
  const bool ortho = cam.type == "orthographic";
  if (!ortho && cam.type != "perspective") return fmt::format("{} cameras are not supported", cam.type);
  const Vec3 forward = -world.column(2), up = world.column(1), eye = world.column(3);
  const double yfov = cam.perspective.yfov * 180.0 / 3.14159265358979323846;
  // glTF's ymag is the orthographic view's half-height; node scale does not change it.
  const double ymag = std::fabs(cam.orthographic.ymag);
  if (!is_finite(eye) || !is_finite(forward) || !is_finite(up) || !(dot(forward, forward) > 0.f) ||
      !(dot(up, up) > 0.f) || !(ortho ? ymag > 0.0 && ymag < 1e30 : yfov > 0.0 && yfov < 180.0))
    return ortho ? "its transform or magnification is degenerate" : "its transform or field of view is degenerate";
  // The target is one unit ahead: only the direction matters to the camera model.
  out.eye = eye;
  out.target = eye + normalize(forward);
  out.up = normalize(up);
  out.vfov_deg = ortho ? Camera{}.vfov_deg : static_cast<float>(yfov);
  out.ortho_half_height = ortho ? static_cast<float>(ymag) : 0.f;
  out.from_file = true;
  return {};
}

std::vector<FileCamera> GltfReader::cameras() const {
  std::vector<FileCamera> out;
  std::vector<uint8_t> seen(model_.nodes.size(), 0);
  for (int root : root_nodes()) {
    std::vector<std::pair<int, Mat4>> stack{{root, Mat4{}}};
    while (!stack.empty()) {
      auto [index, parent_world] = stack.back();
      stack.pop_back();
      if (index < 0 || static_cast<size_t>(index) >= model_.nodes.size() || seen[static_cast<size_t>(index)]++)
        continue;  // read() reports these
      const tinygltf::Node& node = model_.nodes[static_cast<size_t>(index)];
      const Mat4 world = parent_world * local_transform(node);
      if (node.camera >= 0) {
        FileCamera fc;
        fc.name = node.name;
        if (fc.name.empty() && static_cast<size_t>(node.camera) < model_.cameras.size())
          fc.name = model_.cameras[static_cast<size_t>(node.camera)].name;
        if (fc.name.empty()) fc.name = fmt::format("camera{}", out.size());
        fc.unusable = camera_of(node, world, fc.camera);
        out.push_back(fc);
      }
      for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) stack.emplace_back(*it, world);
    }
  }
  return out;
}

}  // namespace raycoh::gltf
