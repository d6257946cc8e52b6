// finalize_scene (scenes/scene.h): what every loaded scene goes through before it is traced — validation,
// material sanitising, origin rebasing, normal repair and surface areas, bounds, emitters, the default camera and
// the lighting rule (scenes/scene.cpp's header says it in words).
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "core/params.h"
#include "scenes/gltf_cameras.h"
#include "scenes/scene.h"

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

}  // namespace raycoh
