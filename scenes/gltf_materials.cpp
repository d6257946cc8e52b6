// glTF material mapping: a tinygltf::Material becomes a classified raycoh Material. It reads the
// pbrMetallicRoughness factors, emissiveFactor x KHR_materials_emissive_strength, KHR_materials_transmission,
// KHR_materials_ior and KHR_materials_volume (present = solid, absent = thin-walled), and notes whether any
// texture is referenced (gltf_textures.cpp then scales the factors per triangle by the decoded textures). Part of
// the glTF loader, the one adapter for tinygltf.
#include <fmt/format.h>

#include "scenes/gltf_reader.h"

namespace raycoh::gltf {

namespace {

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

}  // namespace

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

}  // namespace raycoh::gltf
