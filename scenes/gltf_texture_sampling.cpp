// Texture references and sampling of the glTF loader (scenes/gltf_texture_sampling.h).
#include "scenes/gltf_texture_sampling.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/srgb_decode.h"

namespace raycoh::gltf {

namespace {

double number_of(const tinygltf::Value& v, const char* key, int i, double def) {
  if (!v.Has(key)) return def;
  const tinygltf::Value& x = v.Get(key);
  if (i >= 0) {
    if (!x.IsArray() || x.ArrayLen() <= static_cast<size_t>(i) || !x.Get(i).IsNumber()) return def;
    return x.Get(i).GetNumberAsDouble();
  }
  return x.IsNumber() ? x.GetNumberAsDouble() : def;
}

// Texel index i of n under a glTF wrap mode: the same rule as the traversal's alpha test (core/alpha_mask.h).
int wrap(int i, int n, int mode) { return alpha_wrap(i, n, alpha_wrap_mode(mode)); }

// Quantised values of a derived material: its key, and the values it stands for.
constexpr float kColourSteps = 64.f, kFactorSteps = 32.f, kEmissionSteps = 256.f;
int q(float v, float steps) { return static_cast<int>(std::lround(v * steps)); }

}  // namespace

TextureRef texture_ref(const tinygltf::Model& model, int index, int texcoord, const tinygltf::ExtensionMap& ext) {
  TextureRef r;
  if (index < 0 || static_cast<size_t>(index) >= model.textures.size()) return r;
  const tinygltf::Texture& tex = model.textures[static_cast<size_t>(index)];
  if (tex.source < 0 || static_cast<size_t>(tex.source) >= model.images.size()) return r;
  const tinygltf::Image& img = model.images[static_cast<size_t>(tex.source)];
  if (img.width < 1 || img.height < 1 || img.component != 4 || img.bits != 8 ||
      img.image.size() != 4 * static_cast<size_t>(img.width) * static_cast<size_t>(img.height))
    return r;
  r.image = &img;
  r.texcoord = texcoord;
  if (tex.sampler >= 0 && static_cast<size_t>(tex.sampler) < model.samplers.size()) {
    r.wrap_s = model.samplers[static_cast<size_t>(tex.sampler)].wrapS;
    r.wrap_t = model.samplers[static_cast<size_t>(tex.sampler)].wrapT;
  }
  const auto it = ext.find("KHR_texture_transform");
  if (it != ext.end() && it->second.IsObject()) {
    const tinygltf::Value& t = it->second;
    const double ox = number_of(t, "offset", 0, 0), oy = number_of(t, "offset", 1, 0);
    const double rot = number_of(t, "rotation", -1, 0);
    const double sx = number_of(t, "scale", 0, 1), sy = number_of(t, "scale", 1, 1);
    const double c = std::cos(rot), s = std::sin(rot);
    // Rotation counter-clockwise in UV space with v pointing down (the extension's example: offset [0, 1],
    // rotation pi/2, scale 0.5 picks the lower-left quadrant).
    r.m[0] = c * sx, r.m[1] = s * sy, r.m[2] = ox;
    r.m[3] = -s * sx, r.m[4] = c * sy, r.m[5] = oy;
    if (t.Has("texCoord") && t.Get("texCoord").IsInt()) r.texcoord = t.Get("texCoord").GetNumberAsInt();
  }
  return r;
}

TextureRef extension_texture(const tinygltf::Model& model, const tinygltf::ExtensionMap& ext, const char* name,
                             const char* key) {
  const auto it = ext.find(name);
  if (it == ext.end() || !it->second.IsObject() || !it->second.Has(key)) return {};
  const tinygltf::Value& info = it->second.Get(key);
  if (!info.IsObject() || !info.Has("index") || !info.Get("index").IsInt()) return {};
  const int texcoord = info.Has("texCoord") && info.Get("texCoord").IsInt() ? info.Get("texCoord").GetNumberAsInt() : 0;
  tinygltf::ExtensionMap nested;
  if (info.Has("extensions") && info.Get("extensions").IsObject()) {
    const tinygltf::Value& e = info.Get("extensions");
    if (e.Has("KHR_texture_transform")) nested["KHR_texture_transform"] = e.Get("KHR_texture_transform");
  }
  return texture_ref(model, info.Get("index").GetNumberAsInt(), texcoord, nested);
}

uint32_t alpha_wrap_mode(int gltf_wrap) {
  if (gltf_wrap == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return kWrapClamp;
  if (gltf_wrap == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT) return kWrapMirror;
  return kWrapRepeat;
}

std::array<float, 4> sample(const TextureRef& r, float u0, float v0) {
  const double u = r.m[0] * u0 + r.m[1] * v0 + r.m[2], v = r.m[3] * u0 + r.m[4] * v0 + r.m[5];
  const int w = r.image->width, h = r.image->height;
  const double x = u * w - 0.5, y = v * h - 0.5;
  // Texture coordinates far outside [0, 1] are clamped or wrapped (by whole mirror periods) before they reach int.
  auto start = [](double c, int n, int mode) {
    const double f = std::floor(c);
    return static_cast<int>(mode == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE ? std::clamp(f, -1.0, double(n))
                                                                        : std::fmod(f, 2.0 * n));
  };
  const double fx = std::floor(x), fy = std::floor(y);
  const int x0 = start(x, w, r.wrap_s), y0 = start(y, h, r.wrap_t);
  const float ax = static_cast<float>(x - fx), ay = static_cast<float>(y - fy);
  std::array<float, 4> out{0, 0, 0, 0};
  for (int k = 0; k < 4; ++k) {
    const int xi = wrap(x0 + (k & 1), w, r.wrap_s), yi = wrap(y0 + (k >> 1), h, r.wrap_t);
    const float wk = ((k & 1) ? ax : 1.f - ax) * ((k >> 1) ? ay : 1.f - ay);
    const unsigned char* p = &r.image->image[4 * (static_cast<size_t>(yi) * static_cast<size_t>(w) + xi)];
    for (int c = 0; c < 4; ++c) out[c] += wk * (p[c] / 255.f);
  }
  return out;
}

SurfaceTexture surface_texture(const TextureRef& r, uint64_t offset) {
  SurfaceTexture t;
  t.width = static_cast<uint32_t>(r.image->width);
  t.height = static_cast<uint32_t>(r.image->height);
  t.offset = offset;
  t.wrap_s = alpha_wrap_mode(r.wrap_s);
  t.wrap_t = alpha_wrap_mode(r.wrap_t);
  t.texcoord = static_cast<uint32_t>(std::clamp(r.texcoord, 0, 1));
  for (int k = 0; k < 6; ++k) t.m[k] = static_cast<float>(r.m[k]);
  return t;
}

std::array<std::array<float, 2>, 16> sample_points() {
  std::array<std::array<float, 2>, 16> out{};
  int n = 0;
  for_subtriangle_centroids(4, [&](float b1, float b2) { out[n++] = {b1, b2}; });
  return out;
}

SampleSums sample_triangle(const MaterialTextures& mt, const tinygltf::Material& gm, const Material& base,
                           const std::vector<float> (&uv_of)[2], const uint32_t* idx,
                           const std::array<std::array<float, 2>, 16>& points) {
  SampleSums s;
  for (const auto& b : points) {
    float uv[2][2];
    for (int set = 0; set < 2; ++set)
      for (int c = 0; c < 2; ++c)
        uv[set][c] = uv_of[set][2 * idx[0] + c] * (1.f - b[0] - b[1]) + uv_of[set][2 * idx[1] + c] * b[0] +
                     uv_of[set][2 * idx[2] + c] * b[1];
    auto at = [&](const TextureRef& r) {
      const int set = std::clamp(r.texcoord, 0, 1);
      return sample(r, uv[set][0], uv[set][1]);
    };
    float alpha = gm.pbrMetallicRoughness.baseColorFactor.size() >= 4
                      ? static_cast<float>(gm.pbrMetallicRoughness.baseColorFactor[3])
                      : 1.f;
    float c[3], m, ro, e[3], tr;
    if (mt.base) {
      const auto texel = at(mt.base);
      for (int k = 0; k < 3; ++k) c[k] = srgb_to_linear(texel[k]) * base.base_color[k];
      alpha *= texel[3];
    } else {
      for (int k = 0; k < 3; ++k) c[k] = base.base_color[k];
    }
    if (mt.metal_rough) {
      const auto texel = at(mt.metal_rough);  // glTF: green = roughness, blue = metalness
      ro = texel[1] * base.roughness;
      m = texel[2] * base.metallic;
    } else {
      ro = base.roughness;
      m = base.metallic;
    }
    if (mt.emissive) {
      const auto texel = at(mt.emissive);
      for (int k = 0; k < 3; ++k) e[k] = srgb_to_linear(texel[k]) * base.emission[k];
    } else {
      for (int k = 0; k < 3; ++k) e[k] = base.emission[k];
    }
    tr = mt.transmission ? at(mt.transmission)[0] * base.transmission : base.transmission;
    const bool is_opaque = alpha >= static_cast<float>(gm.alphaCutoff);
    s.opaque += is_opaque;
    for (int j = 0; j < 2; ++j) {
      if (j == 1 && !is_opaque) continue;
      for (int k = 0; k < 3; ++k) {
        s.colour[j][k] += c[k];
        s.emission[j][k] += e[k];
      }
      s.metal[j] += m;
      s.rough[j] += ro;
      s.trans[j] += tr;
    }
  }
  return s;
}

std::array<int, 11> derived_key(uint32_t mat, const SampleSums& s, bool masked, size_t samples) {
  const int j = masked && s.opaque > 0 ? 1 : 0;
  const float inv = 1.f / static_cast<float>(j ? s.opaque : static_cast<int>(samples));
  return {static_cast<int>(mat),
          q(s.colour[j][0] * inv, kColourSteps),
          q(s.colour[j][1] * inv, kColourSteps),
          q(s.colour[j][2] * inv, kColourSteps),
          q(s.metal[j] * inv, kFactorSteps),
          q(s.rough[j] * inv, kFactorSteps),
          q(s.emission[j][0] * inv, kEmissionSteps),
          q(s.emission[j][1] * inv, kEmissionSteps),
          q(s.emission[j][2] * inv, kEmissionSteps),
          q(s.trans[j] * inv, kFactorSteps),
          0};
}

Material derived_material(const Material& base, const std::array<int, 11>& key, size_t number) {
  Material d = base;
  d.name = fmt::format("{}#{}", base.name, number);
  for (int k = 0; k < 3; ++k) {
    d.base_color[k] = static_cast<float>(key[1 + k]) / kColourSteps;
    d.emission[k] = static_cast<float>(key[6 + k]) / kEmissionSteps;
  }
  d.metallic = static_cast<float>(key[4]) / kFactorSteps;
  d.roughness = static_cast<float>(key[5]) / kFactorSteps;
  d.transmission = static_cast<float>(key[9]) / kFactorSteps;
  d.cls = classify_material(d);
  return d;
}

}  // namespace raycoh::gltf
