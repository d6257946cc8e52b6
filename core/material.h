// Material classes and the per-shading-point BSDF parameters that host and device code read.
#pragma once

#include "core/vec.h"

namespace raycoh {

// The classes the generators and the path tracer dispatch on (docs/design.md section 6).
enum class MaterialClass : uint8_t { Diffuse = 0, Glossy = 1, Specular = 2, Transmissive = 3, Emissive = 4 };
constexpr int kMaterialClassCount = 5;

// What sampling needs of a material, as a plain struct (the host Material also has names and flags).
// Roughness at or below which a glossy lobe is called specular, and above which a non-metal is diffuse.
constexpr float kSpecularRoughness = 0.05f;
constexpr float kGlossyRoughness = 0.4f;

// The classification rule, the one place it is written (host materials through scenes/scene.h
// classify_material, and every shading point of a textured material at its texel, core/surface_textures.h):
// emissive > transmissive (KHR_materials_transmission replaces only the dielectric part, so a metal stays a metal)
// > specular/glossy (rough enough or metallic) > diffuse. max_emission is the largest emitted radiance component.
RAYCOH_HD RAYCOH_INLINE MaterialClass classify(float max_emission, float transmission, float metallic,
                                               float roughness) {
  if (max_emission > 0.f) return MaterialClass::Emissive;
  if (transmission * (1.f - metallic) > 0.5f) return MaterialClass::Transmissive;
  if (roughness <= kSpecularRoughness) return MaterialClass::Specular;
  if (roughness <= kGlossyRoughness || metallic >= 0.5f) return MaterialClass::Glossy;
  return MaterialClass::Diffuse;
}

struct BsdfParams {
  MaterialClass cls = MaterialClass::Diffuse;
  Vec3 base_color{0.8f, 0.8f, 0.8f};
  float roughness = 1.f;
  float metallic = 0.f;
  float ior = 1.5f;
  bool thin_walled = true;
};

}  // namespace raycoh
