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

// Emitters whose mean exitance over all surfaces is below this light the scene less than a 1/250 of what the
// sun does (Lost Empire's lava: about 1e-4); the sky + sun is added on top of them.
constexpr double kMinEmitterExitance = 0.01;

constexpr Vec3 kSunRadiance{10000.f, 9500.f, 9000.f};  // x 2.5e-4 sr (the sun disc) = about 2.4 irradiance
constexpr Vec3 kSkyZenith{0.12f, 0.22f, 0.5f};
constexpr Vec3 kSkyHorizon{0.4f, 0.5f, 0.65f};

// Default view: from the front, a little right and above, as most models face +Z with +Y up.
constexpr Vec3 kDefaultViewDir{0.2f, 0.3f, 1.f};
constexpr float kDefaultVfovDeg = 45.f;

float luminance(Vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

float sanitize(float v, float def, float lo, float hi) { return std::isfinite(v) ? std::clamp(v, lo, hi) : def; }

}  // namespace

void sanitize_material(Material& m) {
  for (int i = 0; i < 3; ++i) {
    m.base_color[i] = sanitize(m.base_color[i], 0.8f, 0.f, 1.f);
    m.emission[i] = sanitize(m.emission[i], 0.f, 0.f, FLT_MAX);
  }
  m.roughness = sanitize(m.roughness, 1.f, 0.f, 1.f);
  m.metallic = sanitize(m.metallic, 0.f, 0.f, 1.f);
  m.transmission = sanitize(m.transmission, 0.f, 0.f, 1.f);
  // An ior below 1 would make every refraction a total internal reflection; such values are typos in MTL files.
  m.ior = m.ior >= 1.f && std::isfinite(m.ior) ? std::min(m.ior, 4.f) : 1.5f;
  m.cls = classify_material(m);
}

namespace {

// Camera values from a file can be NaN or place the target on the eye; such a view is replaced by the default.
bool camera_usable(const Camera& c) {
  const Vec3 d = c.target - c.eye;
  const bool view = c.ortho_half_height > 0.f ? std::isfinite(c.ortho_half_height)
                                              : c.ortho_half_height == 0.f && c.vfov_deg > 0.f && c.vfov_deg < 180.f;
  return is_finite(c.eye) && is_finite(c.target) && is_finite(c.up) && dot(d, d) > 0.f &&
         length(cross(d, c.up)) > 0.f && view;
}

Camera default_camera(const Bounds& b) {
  Camera cam;
  const Vec3 c = b.center();
  float r = 0.5f * length(b.extent());
  // The eye must differ from the target even when all vertices coincide or the scene sits far from the origin.
  const float ulp_scale = std::max({std::fabs(c.x), std::fabs(c.y), std::fabs(c.z), 1e-30f}) * FLT_EPSILON;
  if (!(r > 0.f)) r = 1.f;
  const float half_fov = 0.5f * kDefaultVfovDeg * 3.14159265358979f / 180.f;
  const float dist = std::max(r / std::sin(half_fov), 16.f * ulp_scale);
  cam.eye = c + normalize(kDefaultViewDir) * dist;
  cam.target = c;
  cam.up = {0.f, 1.f, 0.f};
  cam.vfov_deg = kDefaultVfovDeg;
  cam.from_file = false;
  return cam;
}

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

namespace {

// Counts, finite positions, and indices and materials in range; an empty material list gets a default material,
// and every material is sanitised. A problem is an Error naming the scene.
void validate_scene(Scene& scene) {
  const std::string& who = scene.source.empty() ? scene.name : scene.source;
  auto fail = [&](const std::string& what) { throw Error(fmt::format("scene '{}': {}", who, what)); };

  if (scene.indices.size() % 3 != 0) fail(fmt::format("{} indices is not a multiple of 3", scene.indices.size()));
  const size_t tris = scene.triangle_count();
  if (tris == 0) fail("no triangles");
  if (scene.tri_material.size() != tris)
    fail(fmt::format("{} triangles but {} per-triangle materials", tris, scene.tri_material.size()));
  if (scene.positions.size() > UINT32_MAX) fail(fmt::format("{} vertices is too many", scene.positions.size()));
  for (size_t i = 0; i < scene.positions.size(); ++i) {
    const Vec3 p = scene.positions[i];
    if (!is_finite(p)) fail(fmt::format("vertex {} has a non-finite position ({}, {}, {})", i, p.x, p.y, p.z));
  }
  for (size_t i = 0; i < scene.indices.size(); ++i) {
    if (scene.indices[i] >= scene.positions.size())
      fail(fmt::format("triangle {} uses vertex {}, but there are {} vertices", i / 3, scene.indices[i],
                       scene.positions.size()));
  }
  if (scene.materials.empty()) scene.materials.push_back(Material{"default"});
  for (size_t t = 0; t < tris; ++t) {
    if (scene.tri_material[t] >= scene.materials.size())
      fail(fmt::format("triangle {} uses material {}, but there are {} materials", t, scene.tri_material[t],
                       scene.materials.size()));
  }
  for (Material& m : scene.materials) sanitize_material(m);
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    PunctualLight& l = scene.lights[i];
    const std::string name = fmt::format("{} light {} '{}'", to_string(l.type), i, l.name);
    if (!is_finite(l.position) || !is_finite(l.direction) || !is_finite(l.intensity) || !std::isfinite(l.range) ||
        !std::isfinite(l.cos_inner) || !std::isfinite(l.cos_outer))
      fail(fmt::format("{} has a non-finite position, direction, intensity, range or cone", name));
    if (std::min(l.intensity.x, std::min(l.intensity.y, l.intensity.z)) < 0.f || l.range < 0.f)
      fail(fmt::format("{} has a negative intensity or range", name));
    if (l.type != LightType::Point) {
      if (!(dot(l.direction, l.direction) > 0.f)) fail(fmt::format("{} has a zero direction", name));
      l.direction = normalize(l.direction);
    }
  }
}

// Normalises the usable normals and marks the others for repair: a normal is repaired when it is missing (the
// loaders store zero), non-finite or too short to normalise. Returns whether any vertex needs repair.
bool mark_normals_for_repair(Scene& scene, std::vector<uint8_t>& repair) {
  if (scene.normals.size() != scene.positions.size()) {
    scene.normals.assign(scene.positions.size(), Vec3{0.f, 0.f, 0.f});
    scene.generated_normals = true;
  }
  repair.assign(scene.positions.size(), 0);
  bool any_repair = false;
  for (size_t i = 0; i < scene.normals.size(); ++i) {
    Vec3& n = scene.normals[i];
    const float len2 = dot(n, n);
    if (!is_finite(n) || !(len2 > 1e-20f)) {
      repair[i] = 1;
      any_repair = true;
    } else if (std::fabs(len2 - 1.f) > 1e-6f) {
      n = n * (1.f / std::sqrt(len2));
    }
  }
  return any_repair;
}

// Face normals (area-weighted, i.e. the unnormalised cross product) serve degenerate-triangle counting,
// surface areas for the lighting rule, and normal repair. Returns the triangle areas.
std::vector<float> repair_normals_and_measure(Scene& scene) {
  const size_t tris = scene.triangle_count();
  std::vector<float> areas(tris);
  std::vector<uint8_t> repair;
  const bool any_repair = mark_normals_for_repair(scene, repair);
  std::vector<Vec3> accum(any_repair ? scene.positions.size() : 0, Vec3{0.f, 0.f, 0.f});
  uint32_t degenerate = 0;
  for (size_t t = 0; t < tris; ++t) {
    const uint32_t* idx = &scene.indices[3 * t];
    const Vec3 p0 = scene.positions[idx[0]], p1 = scene.positions[idx[1]], p2 = scene.positions[idx[2]];
    const Vec3 c = cross(p1 - p0, p2 - p0);
    const float len = length(c);
    areas[t] = 0.5f * (std::isfinite(len) ? len : 0.f);
    if (!(len > 0.f)) ++degenerate;
    if (any_repair && std::isfinite(len)) {
      for (int k = 0; k < 3; ++k)
        if (repair[idx[k]]) accum[idx[k]] += c;
    }
  }
  scene.degenerate_tris = degenerate;
  if (degenerate == tris) {
    const std::string& who = scene.source.empty() ? scene.name : scene.source;
    throw Error(
        fmt::format("scene '{}': all {} triangles have zero area in float (collapsed by their scale or "
                    "position?); nothing can be hit",
                    who, tris));
  }
  if (any_repair) {
    for (size_t i = 0; i < scene.normals.size(); ++i) {
      if (!repair[i]) continue;
      const Vec3 a = accum[i];
      const float len2 = dot(a, a);
      // A vertex used only by zero-area triangles (or by none) is never shaded; any unit vector will do.
      scene.normals[i] = len2 > 0.f && std::isfinite(len2) ? a * (1.f / std::sqrt(len2)) : Vec3{0.f, 1.f, 0.f};
    }
  }
  return areas;
}

// Fills the emitter list; returns whether the emitters are too weak to light the scene (the lighting rule).
bool collect_emitters(Scene& scene, const std::vector<float>& areas) {
  scene.emissive_tris.clear();
  double emitted = 0.0, total_area = 0.0;
  for (size_t t = 0; t < scene.triangle_count(); ++t) {
    total_area += areas[t];
    const Material& m = scene.materials[scene.tri_material[t]];
    // An emissive texture decides by the triangle's mean texel emission, else the material's class does.
    const bool textured = scene.textures.emission_textured(t);
    const Vec3 e = textured ? scene.textures.tri_emission[t] : m.emission;
    const bool emits = textured ? max_component(e) > 0.f : m.cls == MaterialClass::Emissive;
    // Zero-area emitters can never be hit or sampled, so they are left out of the emitter list.
    if (emits && areas[t] > 0.f) {
      scene.emissive_tris.push_back(static_cast<uint32_t>(t));
      emitted += 3.14159265358979 * areas[t] * luminance(e);
    }
  }
  return total_area > 0.0 ? emitted / total_area < kMinEmitterExitance : true;
}

// The sky + sun when the scene has no punctual light and no emitter or only weak ones; the sun direction made a
// unit vector.
void set_environment(Scene& scene, bool weak_emitters) {
  scene.env.enabled = scene.lights.empty() && (scene.emissive_tris.empty() || weak_emitters);
  if (scene.env.enabled && max_component(scene.env.sun_radiance) <= 0.f) {
    scene.env.sun_radiance = kSunRadiance;
    scene.env.sky_zenith = kSkyZenith;
    scene.env.sky_horizon = kSkyHorizon;
  }
  if (!is_finite(scene.env.sun_dir) || !(dot(scene.env.sun_dir, scene.env.sun_dir) > 0.f))
    scene.env.sun_dir = Environment{}.sun_dir;
  scene.env.sun_dir = normalize(scene.env.sun_dir);
}

// Origin rebasing, both steps exact in float. An axis whose box centre c lies further from 0 than 8 times the
// box's largest extent E is moved by -c: every coordinate v on it is within E / 2 of c, so v / c lies in
// [15/16, 17/16] and v - c is exact (Sterbenz). Then a box smaller than 1/16 is scaled by the power of two that
// brings E into [1, 2) (exact barring underflow). The camera moves with the scene (its eye may round), and so
// do punctual lights: their positions and ranges like geometry, point and spot intensities by scale^2 so that
// the irradiance I / d^2 they give is unchanged.
void rebase(Scene& scene) {
  Bounds b;
  for (uint32_t i : scene.indices) b.grow(scene.positions[i]);
  const Vec3 c = b.center(), e = b.extent();
  const float extent = std::max(e.x, std::max(e.y, e.z));
  if (!(extent > 0.f) || !std::isfinite(extent)) return;
  Vec3 offset{0.f, 0.f, 0.f};
  for (int k = 0; k < 3; ++k)
    if (std::fabs(c[k]) > 8.f * extent) offset[k] = c[k];
  const float scale = extent < 1.f / 16.f ? std::ldexp(1.f, -std::ilogb(extent)) : 1.f;
  if (offset.x == 0.f && offset.y == 0.f && offset.z == 0.f && scale == 1.f) return;
  for (Vec3& p : scene.positions) p = (p - offset) * scale;
  scene.camera.eye = (scene.camera.eye - offset) * scale;
  scene.camera.target = (scene.camera.target - offset) * scale;
  scene.camera.ortho_half_height *= scale;
  for (PunctualLight& l : scene.lights) {
    l.position = (l.position - offset) * scale;
    l.range *= scale;
    if (l.type != LightType::Directional) l.intensity = l.intensity * (scale * scale);
  }
  scene.rebase_offset = offset;
  scene.rebase_scale = scale;
}

}  // namespace

void finalize_scene(Scene& scene) {
  validate_scene(scene);
  rebase(scene);
  const std::vector<float> areas = repair_normals_and_measure(scene);

  scene.bounds = Bounds{};
  for (uint32_t i : scene.indices) scene.bounds.grow(scene.positions[i]);

  const bool weak = collect_emitters(scene, areas);
  if (!camera_usable(scene.camera) || !scene.camera.from_file) scene.camera = default_camera(scene.bounds);
  set_environment(scene, weak);
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
