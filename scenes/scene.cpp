// What every loader shares: material classification, load_scene's dispatch (a built-in name, else a file, else a
// directory holding one scene file), finalize_scene (validation, normals, bounds, emitters, default camera,
// sky + sun) and analyse(), which says what a scene needs and which pipeline stages a run on it leaves out.
//
// Lighting rule (finalize_scene): a scene with punctual lights (glTF KHR_lights_punctual) is lit by them and its
// emitters, never by a substituted sky. Otherwise the sky + sun environment is switched on when a scene has no
// emitting triangle, or when its emitters are too weak to light it: their mean radiant exitance over the scene's whole
// surface, pi * sum(area * luminance(emission)) / total area, is below kMinEmitterExitance. The sun then gives
// about 2.4 W/m^2 at normal incidence and the sky about 1 more, so a white wall in the open reads about 0.5-1.
#include "scenes/scene.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "core/params.h"
#include "scenes/gltf_cameras.h"

namespace raycoh {

namespace {

std::string lower(std::string s) {
  for (char& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

bool is_gltf_ext(const std::string& ext) { return ext == ".gltf" || ext == ".glb"; }

Scene load_file(const std::filesystem::path& file, const std::string& spec) {
  const std::string ext = lower(file.extension().string());
  if (is_gltf_ext(ext)) return load_gltf(file.string());
  if (ext == ".obj") return load_obj(file.string());
  throw Error(fmt::format("scene '{}': unknown file type '{}'; expected .gltf, .glb or .obj", spec,
                          ext.empty() ? std::string("(no extension)") : ext));
}

// A directory stands for the one scene file at its top level; glTF wins over OBJ because the shared scenes
// keep a source OBJ next to their GLB.
std::filesystem::path pick_scene_file(const std::filesystem::path& dir, const std::string& spec) {
  std::vector<std::filesystem::path> gltf, obj;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    if (!entry.is_regular_file(ec)) continue;
    const std::string ext = lower(entry.path().extension().string());
    if (is_gltf_ext(ext)) gltf.push_back(entry.path());
    if (ext == ".obj") obj.push_back(entry.path());
  }
  if (ec) throw Error(fmt::format("scene '{}': cannot list the directory: {}", spec, ec.message()));
  const auto& pick = gltf.empty() ? obj : gltf;
  if (pick.size() == 1) return pick.front();
  if (pick.empty())
    throw Error(fmt::format("scene '{}': the directory holds no .gltf, .glb or .obj file at its top level", spec));
  std::vector<std::string> names;
  for (const auto& p : pick) names.push_back(p.filename().string());
  std::sort(names.begin(), names.end());
  throw Error(
      fmt::format("scene '{}': the directory holds several scene files ({}); name one of them", spec, join(names)));
}

// `:camera=N|name` of a glTF file: its N-th camera node (traversal order) or the one of that name. The choices
// are listed by get_choice's error; a degenerate camera is refused naming why. The file's camera is in source
// coordinates: it is moved like the scene was (finalize_scene's rebase).
void select_camera(Scene& scene, const std::string& path, ParamSet& params) {
  std::vector<FileCamera> cams;
  const std::string ext = lower(std::filesystem::path(path).extension().string());
  if (is_gltf_ext(ext)) cams = gltf_cameras(path);
  std::vector<std::string> choices;
  for (size_t i = 0; i < cams.size(); ++i) choices.push_back(std::to_string(i));
  for (const FileCamera& c : cams) choices.push_back(c.name);
  if (choices.empty()) choices.push_back("(none: the file has no camera)");
  const std::string pick = params.get_choice("camera", "", choices);
  if (pick.empty()) return;
  size_t i = 0;
  while (i < cams.size() && std::to_string(i) != pick) ++i;
  if (i == cams.size()) {
    i = 0;
    while (cams[i].name != pick) ++i;
  }
  if (!cams[i].unusable.empty())
    throw Error(fmt::format("scene '{}': camera={} ('{}'): {}", path, pick, cams[i].name, cams[i].unusable));
  Camera cam = cams[i].camera;
  cam.eye = (cam.eye - scene.rebase_offset) * scene.rebase_scale;
  cam.target = (cam.target - scene.rebase_offset) * scene.rebase_scale;
  cam.ortho_half_height *= scene.rebase_scale;
  scene.camera = cam;
}

}  // namespace

const char* to_string(MaterialClass c) {
  switch (c) {
    case MaterialClass::Diffuse:
      return "diffuse";
    case MaterialClass::Glossy:
      return "glossy";
    case MaterialClass::Specular:
      return "specular";
    case MaterialClass::Transmissive:
      return "transmissive";
    case MaterialClass::Emissive:
      return "emissive";
  }
  return "unknown";
}

const char* to_string(LightType t) {
  switch (t) {
    case LightType::Point:
      return "point";
    case LightType::Spot:
      return "spot";
    case LightType::Directional:
      return "directional";
  }
  return "unknown";
}

MaterialClass classify_material(const Material& m) {
  return classify(max_component(m.emission), m.transmission, m.metallic, m.roughness);
}

SceneFeatures analyse(const Scene& scene) {
  SceneFeatures f;
  f.triangles = scene.triangle_count();
  // Only materials some triangle uses count: an unused glossy material must not switch on glossy handling.
  std::vector<uint8_t> used(scene.materials.size(), 0);
  for (uint32_t m : scene.tri_material)
    if (m < used.size()) used[m] = 1;
  size_t textured = 0;
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    if (!used[i]) continue;
    const Material& m = scene.materials[i];
    ++f.materials_per_class[static_cast<int>(m.cls)];
    if (m.has_texture) ++textured;
  }
  f.has_glossy = f.materials_per_class[static_cast<int>(MaterialClass::Glossy)] +
                     f.materials_per_class[static_cast<int>(MaterialClass::Specular)] >
                 0;
  f.has_transmissive = f.materials_per_class[static_cast<int>(MaterialClass::Transmissive)] > 0;
  f.has_emissive = !scene.emissive_tris.empty();
  f.punctual_lights = scene.lights.size();
  f.has_textures = textured > 0;
  f.needs_env_light = scene.env.enabled;

  // glTF textures are folded into per-triangle materials at load time (scenes/gltf_textures.cpp); OBJ texture
  // maps are not read.
  if (!f.has_textures) f.skipped_stages.push_back("texture decoding: scene has no textures");
  if (!f.has_glossy) f.skipped_stages.push_back("hybrid groups: no glossy materials");
  if (!f.has_transmissive) f.skipped_stages.push_back("transmission handling: no transmissive materials");
  if (!f.has_emissive) f.skipped_stages.push_back("emitter sampling: scene has no emitters");
  if (!f.needs_env_light)
    f.skipped_stages.push_back(f.punctual_lights > 0 ? "environment light: scene has punctual lights"
                                                     : "environment light: scene has emitters");
  return f;
}

void check_scene_spec(const std::string& option, const std::string& spec) {
  const std::vector<std::string> builtins = builtin_scene_names();
  const std::string name = parse_plugin_spec(spec).name;
  const size_t colon = spec.rfind(':');
  std::error_code ec;
  const bool exists = std::filesystem::exists(spec, ec) ||
                      (colon != std::string::npos && std::filesystem::exists(spec.substr(0, colon), ec));
  if (std::find(builtins.begin(), builtins.end(), name) == builtins.end() && !exists)
    throw Error(fmt::format("{} {}: neither a built-in scene ({}) nor an existing file or folder", option, spec,
                            join(builtins)));
}

std::string scene_name_of(const std::string& spec) {
  namespace fs = std::filesystem;
  const std::vector<std::string> builtins = builtin_scene_names();
  const PluginSpec plugin = parse_plugin_spec(spec);
  const bool builtin = std::find(builtins.begin(), builtins.end(), plugin.name) != builtins.end();
  if (builtin) return plugin.name;
  std::error_code ec;
  const fs::path path(spec);
  if (!spec.empty() && fs::exists(path, ec))
    return (fs::is_directory(path, ec) ? pick_scene_file(path, spec) : path).stem().string();
  const size_t colon = spec.rfind(':');
  if (colon != std::string::npos && colon > 0 && fs::exists(fs::path(spec.substr(0, colon)), ec))
    return scene_name_of(spec.substr(0, colon));
  return plugin.name;
}

Scene load_scene(const std::string& spec) {
  namespace fs = std::filesystem;
  const std::vector<std::string> builtins = builtin_scene_names();
  const PluginSpec plugin = parse_plugin_spec(spec);
  // A built-in name (with or without parameters) wins over a file or folder of that name in the working directory
  // ("./cornell" means the file).
  const bool builtin = std::find(builtins.begin(), builtins.end(), plugin.name) != builtins.end();
  if (builtin) return make_builtin_scene(spec);
  std::error_code ec;
  const fs::path path(spec);
  if (!spec.empty() && fs::exists(path, ec)) {
    Scene scene;
    if (fs::is_directory(path, ec)) {
      scene = load_file(pick_scene_file(path, spec), spec);
    } else if (fs::is_regular_file(path, ec)) {
      scene = load_file(path, spec);
    } else {
      throw Error(fmt::format("scene '{}': not a regular file or directory", spec));
    }
    scene.source = spec;
    return scene;
  }
  // "path:key=value,...": a file with lighting parameters (paths with ':' are rare; the whole spec was tried
  // as a path first).
  const size_t colon = spec.rfind(':');
  if (colon != std::string::npos && colon > 0 && fs::exists(fs::path(spec.substr(0, colon)), ec)) {
    Scene scene = load_scene(spec.substr(0, colon));
    ParamSet params(fmt::format("scene '{}'", spec.substr(0, colon)), spec.substr(colon + 1));
    const Vec3 sun = params.get_vec3("sun", scene.env.sun_dir, -1e3f, 1e3f);
    // Only a camera choice parses the file a second time (for its camera list).
    if (spec.find("camera=", colon) != std::string::npos) select_camera(scene, spec.substr(0, colon), params);
    params.finish();
    if (!(dot(sun, sun) > 0.f)) throw Error(fmt::format("scene '{}': sun direction must not be zero", spec));
    scene.env.sun_dir = normalize(sun);
    scene.source = spec;
    return scene;
  }
  throw Error(fmt::format("scene '{}': no such file or built-in scene; built-ins: {}", spec, join(builtins)));
}

}  // namespace raycoh
