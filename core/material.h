// Material classes and the per-shading-point BSDF parameters that host and device code read.
#pragma once

#include "core/vec.h"

namespace raycoh {

// The classes the generators and the path tracer dispatch on (DESIGN.md section 6).
enum class MaterialClass : uint8_t { Diffuse = 0, Glossy = 1, Specular = 2, Transmissive = 3, Emissive = 4 };
constexpr int kMaterialClassCount = 5;

// What sampling needs of a material, as a plain struct (the host Material also has names and flags).
struct BsdfParams {
  MaterialClass cls = MaterialClass::Diffuse;
  Vec3 base_color{0.8f, 0.8f, 0.8f};
  float roughness = 1.f;
  float metallic = 0.f;
  float ior = 1.5f;
  bool thin_walled = true;
};

}  // namespace raycoh
