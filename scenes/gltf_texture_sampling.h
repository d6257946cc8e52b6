// Texture references and sampling of the glTF loader (scenes/gltf_textures.cpp's two uses of decoded textures):
// a material's texture references (UV set, KHR_texture_transform, wrap modes), bilinear texel lookup, the per-hit
// SurfaceTexture record, and the per-triangle sampling that becomes a derived material. Part of the one adapter
// for tinygltf; internal to scenes/.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "scenes/gltf_reader.h"

namespace raycoh::gltf {

// One texture reference of a material: image, UV set and the affine UV transform u' = m[0] u + m[1] v + m[2],
// v' = m[3] u + m[4] v + m[5] (KHR_texture_transform: translation x rotation x scale).
struct TextureRef {
  const tinygltf::Image* image = nullptr;
  int texcoord = 0;
  double m[6] = {1, 0, 0, 0, 1, 0};
  int wrap_s = TINYGLTF_TEXTURE_WRAP_REPEAT, wrap_t = TINYGLTF_TEXTURE_WRAP_REPEAT;
  explicit operator bool() const { return image != nullptr; }
};

// The decoded textures of one material.
struct MaterialTextures {
  TextureRef base, metal_rough, emissive, transmission, normal;
  float normal_scale = 1.f;
  bool any() const { return base || metal_rough || emissive || transmission; }
  bool at_hit() const { return any() || normal; }
};

// A triangle's texel values summed over its sample points: [0] over all of them, [1] over the opaque ones.
struct SampleSums {
  float colour[2][3] = {}, metal[2] = {}, rough[2] = {}, emission[2][3] = {}, trans[2] = {};
  int opaque = 0;
};

// Barycentric (b1, b2) of the centroids of the n x n sub-triangles of a triangle split n times along each edge.
template <typename F>
void for_subtriangle_centroids(int n, F&& f) {
  const float s = 1.f / static_cast<float>(n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      f((i + 1.f / 3.f) * s, (j + 1.f / 3.f) * s);
      if (i + j < n - 1) f((i + 2.f / 3.f) * s, (j + 2.f / 3.f) * s);
    }
}

// A decoded image behind texture `index`, with the UV set, transform and wrap modes that apply; empty when the
// texture or its image is missing or was not decoded (tinygltf's warnings say why).
TextureRef texture_ref(const tinygltf::Model& model, int index, int texcoord, const tinygltf::ExtensionMap& ext);
// A texture in an extension object (e.g. KHR_materials_transmission's transmissionTexture).
TextureRef extension_texture(const tinygltf::Model& model, const tinygltf::ExtensionMap& ext, const char* name,
                             const char* key);
// The alpha test's wrap mode (core/alpha_mask.h) of a glTF sampler wrap mode.
uint32_t alpha_wrap_mode(int gltf_wrap);
// Bilinear RGBA in [0, 1] at texture coordinates (u, v) before the reference's transform.
std::array<float, 4> sample(const TextureRef& r, float u0, float v0);
// The per-hit record of a texture whose texels start at `offset` in SurfaceTextures::texels.
SurfaceTexture surface_texture(const TextureRef& r, uint64_t offset);
// Barycentric (b1, b2) of the 16 sample points: centroids of the 16 sub-triangles of a 4 x 4 subdivision.
std::array<std::array<float, 2>, 16> sample_points();
// A triangle's texels at `points`, times the material's factors.
SampleSums sample_triangle(const MaterialTextures& mt, const tinygltf::Material& gm, const Material& base,
                           const std::vector<float> (&uv_of)[2], const uint32_t* idx,
                           const std::array<std::array<float, 2>, 16>& points);
// The quantised mean of a triangle's samples: its derived material's key (material, colour, metallic, roughness,
// emission, transmission). A masked triangle looks like its opaque texels: the others are never hit.
std::array<int, 11> derived_key(uint32_t mat, const SampleSums& s, bool masked, size_t samples);
// The material a derived key stands for: `base` with the key's values, named after it with its number.
Material derived_material(const Material& base, const std::array<int, 11>& key, size_t number);

}  // namespace raycoh::gltf
