// The scenes the device path tracer is held to the CPU one on (tests/gpu_path_tracer_test.cpp: same-seed frames
// bit for bit; tests/gpu_path_tracer_images_test.cpp: whole images within their noise), and what each covers:
// together they put every material class (core/material.h MaterialClass), surface textures, alpha MASK cut-outs and
// every light type (emissive triangles; KHR_lights_punctual point, spot and directional lights; the environment's
// sun and sky gradient, core/environment_light.h: the environment light has no texture map) in front of both
// renderers. GpuPathTracerCoverage checks on the CPU that every scene has what the list says.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/alpha_mask.h"
#include "core/environment_light.h"
#include "generators/pixel_order.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "tests/test_util.h"
#include "tracers/tracer.h"

namespace raycoh::test {

// What a scene puts in front of the renderers. The material classes (MaterialClass's order), textures and masks
// count where the camera sees them (a first hit at the size the scene is rendered); light types where the scene
// has them.
enum Feature : uint32_t {
  kDiffuse = 1u << 0,
  kGlossy = 1u << 1,
  kSpecular = 1u << 2,
  kTransmissive = 1u << 3,
  kEmissive = 1u << 4,
  kTextures = 1u << 5,      // a textured triangle (core/surface_textures.h)
  kAlphaMask = 1u << 6,     // a triangle with an alpha MASK texture (core/alpha_mask.h)
  kEmitterLight = 1u << 7,  // emissive triangles, sampled by next-event estimation
  kPointLight = 1u << 8,    // KHR_lights_punctual (core/light_sampling.h)
  kSpotLight = 1u << 9,
  kDirectionalLight = 1u << 10,
  kSun = 1u << 11,  // the environment's sun, sampled by next-event estimation
  kSky = 1u << 12,  // the environment's sky gradient, found by BSDF sampling only
  kEveryFeature = (1u << 13) - 1,
};

inline std::string feature_list(uint32_t features) {
  static const char* const names[] = {"diffuse",     "glossy",     "specular",          "transmissive",
                                      "emissive",    "textures",   "alpha mask",        "emissive triangles",
                                      "point light", "spot light", "directional light", "sun",
                                      "sky"};
  std::string out;
  for (int b = 0; b < 13; ++b)
    if (features & (1u << b)) out += (out.empty() ? "" : ", ") + std::string(names[b]);
  return out.empty() ? "nothing" : out;
}

// One scene of the list. kind: "builtin" (a built-in spec), "shared" (a .glb stem under the shared scenes), "sample"
// (a glTF sample's folder), "lit cornell" (lit_cornell below). covers: what it has at both test sizes.
// sim_skip: why it is not rendered at the simulator size (it is on a GPU); sim_weak: why the image test cannot
// require the power to reject a 1.5x brighter image at the simulator size (it does at the full size).
struct CoveredScene {
  const char* name;
  const char* kind;
  const char* spec;
  uint32_t covers;
  const char* sim_skip = nullptr;
  const char* sim_weak = nullptr;
  const char* full_weak = nullptr;  // the same at the full size (then only agreement is checked)
};

// The coverage list.
inline const std::vector<CoveredScene>& coverage_list() {
  static const std::vector<CoveredScene> list = {
      {"cornell", "builtin", "cornell", kDiffuse | kGlossy | kEmissive | kEmitterLight},
      {"voxels", "builtin", "voxels:size=24", kDiffuse | kGlossy | kSun | kSky},
      {"lit_cornell", "lit cornell", "cornell",
       kDiffuse | kGlossy | kEmissive | kEmitterLight | kPointLight | kSpotLight | kDirectionalLight},
      {"sibenik_lamps", "shared", "sibenik_lamps", kDiffuse | kTransmissive | kEmitterLight},
      {"conference_lamps", "shared", "conference_lamps", kDiffuse | kEmissive | kEmitterLight, nullptr,
       "16 frames of 16x16 are too noisy to reject a 1.5x brighter image (max |z| 2.66 under GPGPU-Sim, "
       "2026-11-29)"},
      {"country_kitchen", "shared", "country_kitchen",
       kDiffuse | kGlossy | kSpecular | kTransmissive | kEmissive | kEmitterLight},
      {"DamagedHelmet", "sample", "DamagedHelmet",
       kDiffuse | kGlossy | kSpecular | kEmissive | kTextures | kEmitterLight | kSun | kSky},
      {"AlphaBlendModeTest", "sample", "AlphaBlendModeTest", kDiffuse | kGlossy | kTextures | kAlphaMask | kSun | kSky},
      {"LightsPunctualLamp", "sample", "LightsPunctualLamp",
       kGlossy | kTransmissive | kEmissive | kTextures | kEmitterLight | kPointLight, nullptr,
       "16 frames of 16x16 are too noisy to reject a 1.5x brighter image (max |z| 2.46 under GPGPU-Sim, "
       "2026-11-29)",
       "its noise is heavy-tailed: 64x48 cannot tell a 1.1x brighter CPU image (max |z| 1.97 at 128 frames, 2.38 at "
       "1024; GpuPathTracerCoverage.TheZTestRejectsABrighterImageOnTheCpuAlone, 2026-11-29)"},
  };
  return list;
}

inline const CoveredScene& covered(const std::string& name) {
  for (const CoveredScene& c : coverage_list())
    if (name == c.name) return c;
  throw std::invalid_argument("no scene '" + name + "' in the coverage list");
}

// A glTF sample's file (binary first), or empty when the samples or this one are absent.
inline std::filesystem::path sample_file(const std::string& name) {
  const std::filesystem::path dir = gltf_samples_dir();
  if (dir.empty()) return {};
  for (const auto& p : {dir / name / "glTF-Binary" / (name + ".glb"), dir / name / "glTF" / (name + ".gltf")})
    if (std::filesystem::exists(p)) return p;
  return {};
}

inline std::filesystem::path shared_file(const std::string& stem) {
  for (const auto& p : shared_scene_files())
    if (p.stem() == stem) return p;
  return {};
}

// Cornell with a point light under the ceiling, a spot on the floor and a directional light through the open front,
// beside its emitting ceiling: no shared scene or glTF sample has a spot or a directional light.
inline Scene lit_cornell() {
  Scene s = load_scene("cornell");
  PunctualLight point, spot, sun;
  point.name = "point";
  point.position = {-0.5f, 1.7f, 0.3f};
  point.intensity = {2.f, 1.5f, 1.f};
  spot.name = "spot";
  spot.type = LightType::Spot;
  spot.position = {0.4f, 1.8f, 0.6f};
  spot.direction = {-0.2f, -1.f, -0.3f};
  spot.intensity = {1.f, 2.f, 3.f};
  spot.cos_inner = 0.95f;
  spot.cos_outer = 0.8f;
  sun.name = "directional";
  sun.type = LightType::Directional;
  sun.direction = {0.3f, -0.4f, -1.f};
  sun.intensity = {1.f, 1.f, 0.8f};
  s.lights = {point, spot, sun};
  finalize_scene(s);
  return s;
}

// The scene, or nullopt with the reason in `absent` when its file is not there.
inline std::optional<Scene> load_covered(const CoveredScene& c, std::string& absent) {
  const std::string kind = c.kind;
  if (kind == "builtin") return load_scene(c.spec);
  if (kind == "lit cornell") return lit_cornell();
  const std::filesystem::path file = kind == "shared" ? shared_file(c.spec) : sample_file(c.spec);
  if (file.empty()) {
    absent = std::string("no ") + (kind == "shared" ? "shared scene " : "glTF sample ") + c.spec;
    return std::nullopt;
  }
  return load_scene(file.string());
}

// What the scene puts in front of the renderers at width x height: the first hits of frames 0..3 (the camera
// jitters) and its lights.
inline uint32_t features_of(const Scene& scene, int width, int height) {
  const Bvh bvh = build_bvh(scene);
  auto cpu = make_tracer({"cpu", ""}, scene, bvh);
  const auto order = make_pixel_order(width, height, RayOrder::Tile, 8, 8);
  uint32_t f = 0;
  for (uint32_t frame = 0; frame < 4; ++frame) {
    const FirstHits first = first_hits(scene, *cpu, width, height, order, 1, frame);
    for (const ShadingPoint& p : first.gbuffer.points) {
      if (!p.valid()) continue;
      f |= 1u << static_cast<uint32_t>(p.cls);
      if (scene.textures.textured(p.prim)) f |= kTextures;
      if (!scene.alpha.empty() && scene.alpha.tri_texture[p.prim] != kNoAlphaMask) f |= kAlphaMask;
    }
  }
  if (!scene.emissive_tris.empty()) f |= kEmitterLight;
  for (const PunctualLight& l : scene.lights)
    f |= l.type == LightType::Point ? kPointLight : l.type == LightType::Spot ? kSpotLight : kDirectionalLight;
  if (sun_on(scene.env)) f |= kSun;
  if (scene.env.enabled && max_component(scene.env.sky_zenith + scene.env.sky_horizon) > 0.f) f |= kSky;
  return f;
}

}  // namespace raycoh::test
