// Whole G-buffers compared bit for bit (tests/gpu_gbuffer_test.cpp, gpu_pipeline_test.cpp): the header (size,
// frame, hit count, the table's layout), every field of every ShadingPoint and every entry of the material table
// (HitMaterials: BSDF parameters and emission), floats by their bits; padding bytes, which hold whatever a store
// left there, are not compared.
//
// The one place the two sides' maths libraries meet: a textured hit's base colour and emission are sRGB-decoded
// texels (core/surface_textures.h srgb_to_linear calls powf), and CUDA's powf and glibc's round some arguments 1 ulp
// apart (under GPGPU-Sim at 24x16 pixels: 16 of DamagedHelmet's 384 per-pixel slots and 26 of AlphaBlendModeTest's,
// each channel within 1 ulp; roughness and metalness, decoded linearly, equal). compare_gbuffers(a, b, srgb_ulps)
// counts a per-pixel table slot whose fields are all equal but for base-colour or emission channels each within
// srgb_ulps ulps in `srgb` instead of `bsdf` / `emission`; every other field of every point and entry stays bit for
// bit.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <string>
#include <tuple>
#include <vector>

#include "core/material.h"
#include "core/ray_batch.h"

namespace raycoh::test {

struct GBufferDiff {
  size_t header = 0;    // width, height, frame, hits, table present, scene_count, table sizes
  size_t points = 0;    // ShadingPoints that differ in any field
  size_t bsdf = 0;      // table entries whose BSDF parameters differ
  size_t emission = 0;  // table entries whose emission differs
  size_t srgb = 0;      // per-pixel slots apart only in sRGB-decoded channels, within srgb_ulps (not in total)
  size_t total() const { return header + points + bsdf + emission; }
  std::string summary() const {
    return "header " + std::to_string(header) + ", points " + std::to_string(points) + ", table bsdf " +
           std::to_string(bsdf) + ", table emission " + std::to_string(emission) +
           " (sRGB channels within the ulp bound " + std::to_string(srgb) + ")";
  }
};

inline std::array<uint32_t, 3> vec_bits(const Vec3& v) { return std::bit_cast<std::array<uint32_t, 3>>(v); }

inline auto point_bits(const ShadingPoint& p) {
  return std::tuple(vec_bits(p.position), vec_bits(p.ng), vec_bits(p.ns), vec_bits(p.wo), p.prim, p.material, p.cls,
                    p.front_face);
}

inline auto bsdf_bits(const BsdfParams& b) {
  return std::tuple(b.cls, vec_bits(b.base_color), std::bit_cast<uint32_t>(b.roughness),
                    std::bit_cast<uint32_t>(b.metallic), std::bit_cast<uint32_t>(b.ior), b.thin_walled);
}

template <class T, class Bits>
size_t differing_by(const std::vector<T>& a, const std::vector<T>& b, Bits bits) {
  if (a.size() != b.size()) return std::max(a.size(), b.size());
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i) n += bits(a[i]) != bits(b[i]);
  return n;
}

// Each channel of a and b within ulps units in the last place (same sign; a float's bits order its magnitude).
inline bool within_ulps(const Vec3& a, const Vec3& b, int ulps) {
  const std::array<uint32_t, 3> x = vec_bits(a), y = vec_bits(b);
  for (int c = 0; c < 3; ++c) {
    if ((x[c] >> 31) != (y[c] >> 31)) return false;
    const int64_t d = static_cast<int64_t>(x[c]) - static_cast<int64_t>(y[c]);
    if (d > ulps || d < -ulps) return false;
  }
  return true;
}

// Table entry i apart only in its sRGB-decoded channels, each within ulps.
inline bool srgb_only(const HitMaterials& ta, const HitMaterials& tb, size_t i, int ulps) {
  BsdfParams x = ta.bsdf[i];
  x.base_color = tb.bsdf[i].base_color;
  return bsdf_bits(x) == bsdf_bits(tb.bsdf[i]) && within_ulps(ta.bsdf[i].base_color, tb.bsdf[i].base_color, ulps) &&
         within_ulps(ta.emission[i], tb.emission[i], ulps);
}

inline GBufferDiff compare_gbuffers(const GBuffer& a, const GBuffer& b, int srgb_ulps = 0) {
  GBufferDiff d;
  d.header += a.width != b.width;
  d.header += a.height != b.height;
  d.header += a.frame != b.frame;
  d.header += a.hits != b.hits;
  d.points = differing_by(a.points, b.points, point_bits);
  d.header += !a.materials != !b.materials;
  if (!a.materials || !b.materials) return d;
  const HitMaterials& ta = *a.materials;
  const HitMaterials& tb = *b.materials;
  d.header += ta.scene_count != tb.scene_count;
  if (ta.bsdf.size() != tb.bsdf.size() || ta.emission.size() != tb.emission.size() ||
      ta.bsdf.size() != ta.emission.size()) {
    ++d.header;
    return d;
  }
  for (size_t i = 0; i < ta.bsdf.size(); ++i) {
    const bool bsdf = bsdf_bits(ta.bsdf[i]) != bsdf_bits(tb.bsdf[i]);
    const bool emission = vec_bits(ta.emission[i]) != vec_bits(tb.emission[i]);
    if (!bsdf && !emission) continue;
    if (srgb_ulps > 0 && i >= ta.scene_count && srgb_only(ta, tb, i, srgb_ulps)) {
      ++d.srgb;
      continue;
    }
    d.bsdf += bsdf;
    d.emission += emission;
  }
  return d;
}

}  // namespace raycoh::test
