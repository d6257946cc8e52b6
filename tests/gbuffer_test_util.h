// Whole G-buffers compared bit for bit (tests/gpu_gbuffer_test.cpp, gpu_pipeline_test.cpp): the header (size,
// frame, hit count, the table's layout), every field of every ShadingPoint and every entry of the material table
// (HitMaterials: BSDF parameters and emission), floats by their bits; padding bytes, which hold whatever a store
// left there, are not compared.
//
// No field is exempt: a textured hit's base colour and emission are sRGB-decoded texels, and the decode
// (core/srgb_decode.h) evaluates the same float operations on both sides (before it, CUDA's powf and glibc's rounded
// some arguments 1 ulp apart, which this comparison let through).
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
  size_t total() const { return header + points + bsdf + emission; }
  std::string summary() const {
    return "header " + std::to_string(header) + ", points " + std::to_string(points) + ", table bsdf " +
           std::to_string(bsdf) + ", table emission " + std::to_string(emission);
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

inline GBufferDiff compare_gbuffers(const GBuffer& a, const GBuffer& b) {
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
    d.bsdf += bsdf_bits(ta.bsdf[i]) != bsdf_bits(tb.bsdf[i]);
    d.emission += vec_bits(ta.emission[i]) != vec_bits(tb.emission[i]);
  }
  return d;
}

}  // namespace raycoh::test
