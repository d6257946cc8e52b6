// glTF material textures looked up at a hit, written once for host and device.
//
// A triangle of a textured material (base colour, metallic-roughness, emissive, transmission or normal texture
// that was decoded) keeps both texture coordinate sets at its corners and the index of its material's textures.
// At a hit at barycentrics (b1, b2) every texture is sampled at the hit's own (u, v) in the texture's TEXCOORD
// set, through its KHR_texture_transform (bilinear, with the sampler's wrap modes: core/alpha_mask.h's rule, as
// the glTF viewers filter), and the texels times the material's factors are the shading point's BSDF parameters;
// the class follows with core/material.h's classify(), so a shading point's class is that of the texel it hit.
// Colours are 8-bit sRGB (base colour, emissive) converted to linear after filtering (core/srgb_decode.h: the same
// bits on host and device); metallic-roughness, transmission and normal texels are linear. A normal texel tilts the
// interpolated shading normal in the triangle's tangent frame (tangent = dP/du of the normal texture's coordinates,
// bitangent = -dP/dv as in MikkTSpace with glTF's v pointing down; the TANGENT attribute is not read).
#pragma once

#include "core/alpha_mask.h"
#include "core/material.h"
#include "core/platform.h"
#include "core/srgb_decode.h"
#include "core/vec.h"

namespace raycoh {

constexpr uint32_t kNoTexture = 0xFFFFFFFFu;

// One RGBA8 texture at texels[offset ..] (4 bytes a texel, row-major), with its coordinate set and transform
// u' = m[0] u + m[1] v + m[2], v' = m[3] u + m[4] v + m[5].
struct SurfaceTexture {
  uint32_t width = 0, height = 0;
  uint64_t offset = 0;
  uint32_t wrap_s = kWrapRepeat, wrap_t = kWrapRepeat;
  uint32_t texcoord = 0;  // 0 or 1
  float m[6] = {1.f, 0.f, 0.f, 0.f, 1.f, 0.f};
};

// The factors and texture indices (kNoTexture: none) of one textured glTF material.
struct TexturedMaterial {
  uint32_t base = kNoTexture, metal_rough = kNoTexture, emissive = kNoTexture, transmission = kNoTexture,
           normal = kNoTexture;
  Vec3 base_color{1.f, 1.f, 1.f};
  float roughness = 1.f, metallic = 1.f, transmission_factor = 0.f;
  Vec3 emission{0.f, 0.f, 0.f};  // emissiveFactor x strength
  float normal_scale = 1.f;
  float ior = 1.5f;
  bool thin_walled = true;
};

// Non-owning view, valid on whichever side the arrays live.
struct SurfaceTexturesView {
  const uint32_t* tri_material = nullptr;  // per scene triangle: index into materials, or kNoTexture
  const float* tri_uv = nullptr;           // 12 per scene triangle: set 0 (u, v) at v0, v1, v2, then set 1
  const float* tri_tangent = nullptr;      // 4 per scene triangle: unit tangent and the bitangent's sign
  const TexturedMaterial* materials = nullptr;
  const SurfaceTexture* textures = nullptr;
  const uint8_t* texels = nullptr;
};

// Bilinear RGBA in [0, 1] of texture tex at (u, v), already through its transform.
RAYCOH_HD RAYCOH_INLINE void texel_rgba(const SurfaceTexture& tex, const uint8_t* texels, float u, float v,
                                        float out[4]) {
  const int w = static_cast<int>(tex.width), h = static_cast<int>(tex.height);
  const BilinearTaps b = bilinear_taps(w, h, tex.wrap_s, tex.wrap_t, u, v);
  const int xa = b.xa, xb = b.xb, ya = b.ya, yb = b.yb;
  const float ax = b.ax, ay = b.ay;
  const uint8_t* t = texels + tex.offset;
  const uint8_t* p00 = t + 4 * (static_cast<uint64_t>(ya) * w + xa);
  const uint8_t* p01 = t + 4 * (static_cast<uint64_t>(ya) * w + xb);
  const uint8_t* p10 = t + 4 * (static_cast<uint64_t>(yb) * w + xa);
  const uint8_t* p11 = t + 4 * (static_cast<uint64_t>(yb) * w + xb);
  for (int c = 0; c < 4; ++c) {
    const float top = p00[c] * (1.f - ax) + p01[c] * ax;
    const float bottom = p10[c] * (1.f - ax) + p11[c] * ax;
    out[c] = (top * (1.f - ay) + bottom * ay) * (1.f / 255.f);
  }
}

// Coordinates (u0, v0) of the texture's set through its KHR_texture_transform.
RAYCOH_HD RAYCOH_INLINE void texture_uv(const SurfaceTexture& tex, float u0, float v0, float& u, float& v) {
  u = tex.m[0] * u0 + tex.m[1] * v0 + tex.m[2];
  v = tex.m[3] * u0 + tex.m[4] * v0 + tex.m[5];
}

// Texture ti of a textured triangle at the hit's coordinates uv[set][0..1].
RAYCOH_HD RAYCOH_INLINE void lookup(const SurfaceTexturesView& v, uint32_t ti, const float uv[2][2], float out[4]) {
  const SurfaceTexture& tex = v.textures[ti];
  const float* c = uv[tex.texcoord ? 1 : 0];
  float u, w;
  texture_uv(tex, c[0], c[1], u, w);
  texel_rgba(tex, v.texels, u, w, out);
}

// The hit's coordinates of both sets on textured triangle prim at barycentrics (b1, b2).
RAYCOH_HD RAYCOH_INLINE void hit_uv(const SurfaceTexturesView& v, uint32_t prim, float b1, float b2, float uv[2][2]) {
  const float* t = v.tri_uv + 12 * static_cast<uint64_t>(prim);
  const float b0 = 1.f - b1 - b2;
  for (int set = 0; set < 2; ++set)
    for (int c = 0; c < 2; ++c) uv[set][c] = t[6 * set + c] * b0 + t[6 * set + 2 + c] * b1 + t[6 * set + 4 + c] * b2;
}

// Emitted radiance of material m at the hit's coordinates: emissiveFactor x strength x the emissive texel.
RAYCOH_HD RAYCOH_INLINE Vec3 emission_of(const SurfaceTexturesView& v, const TexturedMaterial& m,
                                         const float uv[2][2]) {
  if (m.emissive == kNoTexture || !(max_component(m.emission) > 0.f)) return m.emission;
  float texel[4];
  lookup(v, m.emissive, uv, texel);
  return Vec3{srgb_to_linear(texel[0]), srgb_to_linear(texel[1]), srgb_to_linear(texel[2])} * m.emission;
}

// What the textures say at one hit.
struct SurfaceSample {
  BsdfParams bsdf;
  Vec3 emission{0.f, 0.f, 0.f};
  bool has_normal = false;
  Vec3 normal_ts{0.f, 0.f, 1.f};  // tangent-space normal (x along the tangent, y the bitangent, z the normal)
};

// The material of textured triangle prim (tri_material[prim] != kNoTexture) at barycentrics (b1, b2).
RAYCOH_HD RAYCOH_INLINE SurfaceSample surface_at(const SurfaceTexturesView& v, uint32_t prim, float b1, float b2) {
  const TexturedMaterial& m = v.materials[v.tri_material[prim]];
  float uv[2][2];
  hit_uv(v, prim, b1, b2, uv);
  SurfaceSample s;
  float texel[4];
  s.bsdf.base_color = m.base_color;
  if (m.base != kNoTexture) {
    lookup(v, m.base, uv, texel);
    s.bsdf.base_color =
        Vec3{srgb_to_linear(texel[0]), srgb_to_linear(texel[1]), srgb_to_linear(texel[2])} * m.base_color;
  }
  s.bsdf.roughness = m.roughness;
  s.bsdf.metallic = m.metallic;
  if (m.metal_rough != kNoTexture) {
    lookup(v, m.metal_rough, uv, texel);  // glTF: green = roughness, blue = metalness
    s.bsdf.roughness = texel[1] * m.roughness;
    s.bsdf.metallic = texel[2] * m.metallic;
  }
  s.emission = emission_of(v, m, uv);
  float transmission = m.transmission_factor;
  if (m.transmission != kNoTexture && transmission > 0.f) {
    lookup(v, m.transmission, uv, texel);
    transmission *= texel[0];
  }
  if (m.normal != kNoTexture) {
    lookup(v, m.normal, uv, texel);
    s.has_normal = true;
    s.normal_ts =
        Vec3{(2.f * texel[0] - 1.f) * m.normal_scale, (2.f * texel[1] - 1.f) * m.normal_scale, 2.f * texel[2] - 1.f};
  }
  s.bsdf.ior = m.ior;
  s.bsdf.thin_walled = m.thin_walled;
  s.bsdf.cls = classify(max_component(s.emission), transmission, s.bsdf.metallic, s.bsdf.roughness);
  return s;
}

// The shading normal a normal texel gives: n_ts in the frame of the interpolated normal n (unit) and the
// triangle's tangent (made orthogonal to n) with the bitangent sign; n itself when the frame or result is not
// usable.
RAYCOH_HD RAYCOH_INLINE Vec3 apply_normal_map(const SurfaceTexturesView& v, uint32_t prim, Vec3 n, Vec3 n_ts) {
  const float* tg = v.tri_tangent + 4 * static_cast<uint64_t>(prim);
  Vec3 t{tg[0], tg[1], tg[2]};
  t = t - n * dot(n, t);
  const float tl = dot(t, t);
  if (!(tl > 1e-12f)) return n;
  t = t * (1.f / sqrtf(tl));
  const Vec3 b = cross(n, t) * tg[3];
  const Vec3 out = t * n_ts.x + b * n_ts.y + n * n_ts.z;
  const float ol = dot(out, out);
  if (!(ol > 1e-12f) || !is_finite(out)) return n;
  return out * (1.f / sqrtf(ol));
}

}  // namespace raycoh
