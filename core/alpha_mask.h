// Alpha MASK cut-outs (glTF alphaMode MASK) as an any-hit test of the traversal, written once for host and device.
//
// A triangle of a MASK material with a base-colour texture keeps its texture coordinates (already through the
// texture's KHR_texture_transform, in the texture's TEXCOORD set); a candidate hit at barycentrics (b1, b2) is
// kept only when the texture's alpha there (bilinear, with the sampler's wrap modes, as the glTF viewers filter
// it) times the base colour factor's alpha reaches the material's alphaCutoff. Rejected hits are skipped and
// traversal goes on behind them, so a ray passes through the cut-out parts of a leaf card.
//
// The test is a compile-time filter policy of the traversal (core/traverse.h, core/traverse_cwbvh.h):
// NoAlphaTest accepts every hit and compiles to nothing, so scenes without MASK materials run the same code as
// before; AlphaTest is chosen by a tracer only when the scene has masked triangles.
#pragma once

#include "core/platform.h"
#include "core/vec.h"

namespace raycoh {

constexpr uint32_t kNoAlphaMask = 0xFFFFFFFFu;

// glTF sampler wrap modes, as stored in AlphaTexture.
enum AlphaWrap : uint32_t { kWrapRepeat = 0, kWrapClamp = 1, kWrapMirror = 2 };

// One mask texture: its alpha texels (8-bit, row-major) at texels[offset ..], and its material's rule.
struct AlphaTexture {
  uint32_t width = 0, height = 0;
  uint64_t offset = 0;
  uint32_t wrap_s = kWrapRepeat, wrap_t = kWrapRepeat;
  float factor = 1.f;  // baseColorFactor's alpha
  float cutoff = 0.5f;
};

// Non-owning view, valid on whichever side the arrays live.
struct AlphaMaskView {
  const uint32_t* tri_texture = nullptr;  // per scene triangle: texture index, or kNoAlphaMask
  const float* tri_uv = nullptr;          // 6 per scene triangle: (u, v) at v0, v1, v2
  const AlphaTexture* textures = nullptr;
  const uint8_t* texels = nullptr;
};

// Texel index i of a row or column of n texels under wrap mode `mode`; i is within one mirror period of [0, n).
RAYCOH_HD RAYCOH_INLINE int alpha_wrap(int i, int n, uint32_t mode) {
  if (mode == kWrapClamp) return i < 0 ? 0 : (i >= n ? n - 1 : i);
  if (mode == kWrapMirror) {
    const int period = 2 * n;
    int k = i % period;
    if (k < 0) k += period;
    return k < n ? k : period - 1 - k;
  }
  int k = i % n;
  return k < 0 ? k + n : k;
}

// The first of the two texels a bilinear lookup at texel coordinate x reads, and the weight of the second; x
// far outside the texture is first reduced by whole mirror periods (or clamped), so the int stays in range. A
// coordinate that is not finite (NaN or infinite texture coordinates in a file, or finite ones so large that
// u * width overflows) reads texel 0 with weight 0: converting it to int is undefined (found by fuzz_gltf).
RAYCOH_HD RAYCOH_INLINE int alpha_start(float x, int n, uint32_t mode, float& frac) {
  if (!(x > -3.0e38f && x < 3.0e38f)) {
    frac = 0.f;
    return 0;
  }
  const float f = floorf(x);
  frac = x - f;
  if (mode == kWrapClamp) {
    const float c = f < -1.f ? -1.f : (f > static_cast<float>(n) ? static_cast<float>(n) : f);
    return static_cast<int>(c);
  }
  return static_cast<int>(fmodf(f, 2.f * static_cast<float>(n)));
}

// The four texels of a bilinear lookup at (u, v) on a w x h texture with the given wrap modes, and the weights of
// the second column (ax) and row (ay): one footprint rule for the alpha test and the surface textures.
struct BilinearTaps {
  int xa, xb, ya, yb;
  float ax, ay;
};
RAYCOH_HD RAYCOH_INLINE BilinearTaps bilinear_taps(int w, int h, uint32_t wrap_s, uint32_t wrap_t, float u, float v) {
  BilinearTaps b;
  const int x0 = alpha_start(u * static_cast<float>(w) - 0.5f, w, wrap_s, b.ax);
  const int y0 = alpha_start(v * static_cast<float>(h) - 0.5f, h, wrap_t, b.ay);
  b.xa = alpha_wrap(x0, w, wrap_s), b.xb = alpha_wrap(x0 + 1, w, wrap_s);
  b.ya = alpha_wrap(y0, h, wrap_t), b.yb = alpha_wrap(y0 + 1, h, wrap_t);
  return b;
}

// Bilinear alpha in [0, 1] of texture tex at (u, v).
RAYCOH_HD RAYCOH_INLINE float alpha_at(const AlphaTexture& tex, const uint8_t* texels, float u, float v) {
  const int w = static_cast<int>(tex.width), h = static_cast<int>(tex.height);
  const BilinearTaps b = bilinear_taps(w, h, tex.wrap_s, tex.wrap_t, u, v);
  const uint8_t* t = texels + tex.offset;
  const float top = t[b.ya * w + b.xa] * (1.f - b.ax) + t[b.ya * w + b.xb] * b.ax;
  const float bottom = t[b.yb * w + b.xa] * (1.f - b.ax) + t[b.yb * w + b.xb] * b.ax;
  return (top * (1.f - b.ay) + bottom * b.ay) * (1.f / 255.f);
}

// Whether the hit at barycentrics (b1, b2) (weights of v1 and v2) on scene triangle prim is opaque.
RAYCOH_HD RAYCOH_INLINE bool alpha_opaque(const AlphaMaskView& a, uint32_t prim, float b1, float b2) {
  const uint32_t ti = a.tri_texture[prim];
  if (ti == kNoAlphaMask) return true;
  const float* uv = a.tri_uv + 6 * static_cast<uint64_t>(prim);
  const float b0 = 1.f - b1 - b2;
  const float u = uv[0] * b0 + uv[2] * b1 + uv[4] * b2, v = uv[1] * b0 + uv[3] * b1 + uv[5] * b2;
  const AlphaTexture& tex = a.textures[ti];
  return alpha_at(tex, a.texels, u, v) * tex.factor >= tex.cutoff;
}

// The traversal's filter policies.
struct NoAlphaTest {
  RAYCOH_HD bool accept(uint32_t, float, float) const { return true; }
};

struct AlphaTest {
  AlphaMaskView view;
  RAYCOH_HD bool accept(uint32_t prim, float b1, float b2) const { return alpha_opaque(view, prim, b1, b2); }
};

}  // namespace raycoh
