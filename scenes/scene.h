// The in-memory scene every stage reads: triangles with shading normals, classified materials, a camera,
// emitters and, when the scene has none, a sky + sun environment.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/alpha_mask.h"
#include "core/environment_light.h"
#include "core/light_sampling.h"
#include "core/material.h"
#include "core/surface_textures.h"
#include "core/vec.h"

namespace raycoh {

const char* to_string(MaterialClass c);

struct Material {
  std::string name;
  MaterialClass cls = MaterialClass::Diffuse;
  Vec3 base_color{0.8f, 0.8f, 0.8f};  // linear RGB
  float roughness = 1.f;
  float metallic = 0.f;
  float ior = 1.5f;
  float transmission = 0.f;
  bool thin_walled = true;       // transmissive without KHR_materials_volume
  Vec3 emission{0.f, 0.f, 0.f};  // radiance = emissiveFactor x emissive strength
  bool has_texture = false;      // references an image texture (not decoded unless a stage needs it)
};

// Classification rule (core/material.h classify): emissive > transmissive > specular/glossy (rough enough or
// metallic) > diffuse.
MaterialClass classify_material(const Material& m);
// Non-finite or out-of-range values replaced or clamped, then classified (every loader's materials go through it).
void sanitize_material(Material& m);

struct Camera {
  Vec3 eye{0.f, 0.f, 1.f};
  Vec3 target{0.f, 0.f, 0.f};
  Vec3 up{0.f, 1.f, 0.f};
  float vfov_deg = 45.f;
  // > 0: an orthographic camera whose view is this half-height (glTF ymag; the width follows the image's aspect),
  // rays parallel to eye -> target from the plane through the eye; 0: a pinhole camera with vfov_deg.
  float ortho_half_height = 0.f;
  // true: the source chose the view (a glTF camera node, or a built-in scene's own view);
  // false: default framing of the scene bounds.
  bool from_file = false;
};

// A KHR_lights_punctual light: a delta light (nothing can hit it), sampled by next-event estimation only.
// Intensities are used as the renderer's radiometric units, with no photometric conversion: a point or spot
// light's intensity (candela) is its radiant intensity on the axis, so a surface at distance r facing it receives
// E = I / r^2, and a directional light's (lux) is the irradiance E on a surface facing it. Emissive materials'
// radiance (emissiveFactor x strength, nits) is on the same scale, so lights and emitters keep their ratio.
// LightType: core/light_sampling.h.
const char* to_string(LightType t);

struct PunctualLight {
  std::string name;
  LightType type = LightType::Point;
  Vec3 position{0.f, 0.f, 0.f};    // point and spot
  Vec3 direction{0.f, 0.f, -1.f};  // spot and directional: unit, the way the light travels (the node's -Z)
  Vec3 intensity{1.f, 1.f, 1.f};   // colour x intensity
  // Point and spot: 0 = infinite; else the spec's recommended window clamp(1 - (d / range)^4, 0, 1) on I / d^2.
  float range = 0.f;
  float cos_inner = 1.f, cos_outer = 0.f;  // spot cone: full intensity inside cos_inner, none outside cos_outer
};

// Environment (sky + sun of scenes without emitters): core/environment_light.h.

// Alpha MASK cut-outs that the tracers test at every candidate hit (core/alpha_mask.h): triangles of MASK
// materials with a base-colour texture. Empty (no arrays at all) when the scene has none, and then every tracer
// runs its traversal without the test.
struct AlphaMasks {
  std::vector<uint32_t> tri_texture;  // per triangle: index into textures, or kNoAlphaMask
  std::vector<float> tri_uv;          // 6 per triangle: the texture's (u, v) at v0, v1, v2
  std::vector<AlphaTexture> textures;
  std::vector<uint8_t> texels;  // every texture's alpha, at its offset
  size_t masked_tris = 0;
  bool empty() const { return tri_texture.empty(); }
  AlphaMaskView view() const { return {tri_texture.data(), tri_uv.data(), textures.data(), texels.data()}; }
};

// glTF textures looked up at every hit (core/surface_textures.h): triangles of materials with a decoded base
// colour, metallic-roughness, emissive, transmission or normal texture. Empty (no arrays) when the scene has none:
// then every shading point takes its triangle's material as before.
struct SurfaceTextures {
  std::vector<uint32_t> tri_material;  // per triangle: index into materials, or kNoTexture
  std::vector<float> tri_uv;           // 12 per triangle
  std::vector<float> tri_tangent;      // 4 per triangle
  std::vector<TexturedMaterial> materials;
  std::vector<SurfaceTexture> textures;
  std::vector<uint8_t> texels;  // RGBA8
  // Per triangle (empty when no material has an emissive texture): the mean emitted radiance over the triangle,
  // from its emissive texels (kNoTexture triangles, and those of materials without an emissive texture: unused).
  std::vector<Vec3> tri_emission;
  size_t textured_tris = 0;
  bool empty() const { return tri_material.empty(); }
  bool textured(size_t t) const { return !tri_material.empty() && tri_material[t] != kNoTexture; }
  // Whether triangle t's emission comes from an emissive texture (then tri_emission[t] is its mean).
  bool emission_textured(size_t t) const {
    return textured(t) && !tri_emission.empty() && materials[tri_material[t]].emissive != kNoTexture;
  }
  SurfaceTexturesView view() const {
    return {tri_material.data(), tri_uv.data(), tri_tangent.data(), materials.data(), textures.data(), texels.data()};
  }
};

struct Scene {
  std::string name;                    // short name (file stem or procedural name)
  std::string source;                  // path or procedural spec it was made from
  std::vector<Vec3> positions;         // world space, after node transforms
  std::vector<Vec3> normals;           // per vertex, unit length, same count as positions
  std::vector<uint32_t> indices;       // 3 per triangle
  std::vector<uint32_t> tri_material;  // per triangle, index into materials
  std::vector<Material> materials;
  std::vector<uint32_t> emissive_tris;  // triangles whose material emits
  std::vector<PunctualLight> lights;    // punctual lights (glTF KHR_lights_punctual), world space
  Camera camera;
  Environment env;
  Bounds bounds;
  uint32_t degenerate_tris = 0;  // zero-area triangles (kept; they are never hit)
  size_t alpha_cut_tris = 0;     // triangles removed whole by an alpha MASK (constant alpha below the cutoff)
  AlphaMasks alpha;              // per-texel cut-outs, tested in traversal
  SurfaceTextures textures;      // materials looked up per texel at every hit
  bool generated_normals = false;
  // What the loader did that changes the workload or the materials, one line each, for `scenes info`: each glTF
  // extension used (supported / mapped / ignored), dropped primitives by kind, instancing, tinygltf's warnings.
  std::vector<std::string> load_notes;
  // Where the loaded coordinates came from (finalize_scene, exact): positions = (source - rebase_offset) x
  // rebase_scale. A scene far from the origin compared with its size is moved next to it, and a scene smaller
  // than 1/16 is scaled by a power of two to a size in [1, 2): float ray arithmetic then has the precision it
  // has on a unit scene at the origin (docs/stability.md).
  Vec3 rebase_offset{0.f, 0.f, 0.f};
  float rebase_scale = 1.f;

  size_t triangle_count() const { return indices.size() / 3; }
};

// What a scene contains, and therefore which pipeline stages it needs.
struct SceneFeatures {
  size_t triangles = 0;
  size_t materials_per_class[5] = {0, 0, 0, 0, 0};
  bool has_glossy = false;  // glossy or specular
  bool has_transmissive = false;
  bool has_emissive = false;
  size_t punctual_lights = 0;
  bool has_textures = false;
  bool needs_env_light = false;
  std::vector<std::string> skipped_stages;  // "stage: reason"
};
SceneFeatures analyse(const Scene& scene);

// Load a scene from a spec: a built-in name with optional parameters ("cornell", "voxels:size=96"), a .gltf/.glb
// or .obj file, or a directory holding exactly one such file. Throws raycoh::Error naming the input on failure.
Scene load_scene(const std::string& spec);

// Cheap check, before anything is measured, that a spec names a built-in scene or an existing file or folder
// (optionally followed by ":key=value" parameters); throws raycoh::Error naming `option` and the spec otherwise.
void check_scene_spec(const std::string& option, const std::string& spec);
// The name load_scene(spec) gives the scene (the CSV's `scene` column), without loading it: a built-in's name
// (its parameters are not part of it), else the stem of the file the spec picks.
std::string scene_name_of(const std::string& spec);

// The pieces load_scene dispatches to.
Scene load_gltf(const std::string& path);
Scene load_obj(const std::string& path);
Scene make_builtin_scene(const std::string& spec);  // "cornell", "voxels[:size=N]"
std::vector<std::string> builtin_scene_names();
std::string builtin_scene_summary(const std::string& name);

// Shared post-processing of every loader: validates geometry (finite positions, indices in range, at least one
// triangle), generates missing normals, classifies materials, fills bounds, emitters, camera and environment.
// Lighting rule: a scene with punctual lights is lit by them (and its emitters); otherwise a scene without
// emitters, or with emitters too weak to light it, gets the sky + sun.
void finalize_scene(Scene& scene);

}  // namespace raycoh
