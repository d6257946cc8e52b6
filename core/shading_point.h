// One first hit of the G-buffer (ShadingPoint) in the layout the device reads, and the one function every kernel
// reads a point with (load_point) and the G-buffer kernel writes one with (store_point).
//
// Why 64 bytes in four 16-byte loads: with 4-byte loads of the fields, a warp reading 32 consecutive points issues
// ~15 loads that each touch ~15 cache lines, and the generators were bound by the L1/TEX pipeline's tag lookups,
// not by DRAM (measured on an H100/H200 with Nsight Compute: results/stages/h200-6ebd003/). Four 16-byte loads
// per point move the same records in 4 wide instructions. Padded to 64 bytes so that every point starts on a
// 16-byte boundary (device buffers from cudaMalloc are 256-byte aligned, points are indexed, never offset by bytes).
// A chunk whose fields a kernel does not use is not loaded (the compiler drops the unused load).
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/material.h"
#include "core/platform.h"
#include "core/ray.h"

namespace raycoh {

// One first hit. Normals face the side the camera ray came from (all shared-scene materials are double-sided):
// ng is the geometric normal, ns the interpolated shading normal (tilted by a normal map where the material has
// one) flipped into ng's hemisphere. material indexes the material table of the G-buffer the point belongs to
// (GBuffer::materials, core/ray_batch.h): its first entries are the scene's materials in Scene::materials order,
// and a hit on a textured glTF material has an entry of its own holding the texels at the hit
// (core/surface_textures.h). cls is that entry's class.
// Every byte is a field (no compiler padding) and the padding fields are always zero, so equal points compare
// equal with memcmp.
struct alignas(16) ShadingPoint {
  Vec3 position;
  Vec3 ng;
  Vec3 ns;
  Vec3 wo;  // unit, towards the camera
  uint32_t prim = kNoHit;
  uint32_t material = 0;
  MaterialClass cls = MaterialClass::Diffuse;
  bool front_face = true;  // the camera ray hit the side the triangle's winding faces
  uint16_t pad16 = 0;      // padding, always zero
  uint32_t pad32 = 0;      // padding, always zero
  RAYCOH_HD bool valid() const { return prim != kNoHit; }
};
static_assert(sizeof(ShadingPoint) == 64 && alignof(ShadingPoint) == 16, "a point is four aligned 16-byte words");
static_assert(sizeof(MaterialClass) == 1 && sizeof(bool) == 1, "cls and front_face share a word with pad16");
// The words load_point and store_point move: [0] position, ng.x; [1] ng.yz, ns.xy; [2] ns.z, wo; [3] the rest.
static_assert(offsetof(ShadingPoint, ng) == 12 && offsetof(ShadingPoint, ns) == 24 &&
                  offsetof(ShadingPoint, wo) == 36 && offsetof(ShadingPoint, prim) == 48 &&
                  offsetof(ShadingPoint, material) == 52 && offsetof(ShadingPoint, cls) == 56 &&
                  offsetof(ShadingPoint, front_face) == 57 && offsetof(ShadingPoint, pad16) == 58 &&
                  offsetof(ShadingPoint, pad32) == 60,
              "the field offsets load_point and store_point assume");

// points[i]: on the device four 16-byte read-only loads (the G-buffer is not written while a kernel reads it),
// reassembled field by field; on the host a plain copy. The same bits either way.
RAYCOH_HD RAYCOH_INLINE ShadingPoint load_point(const ShadingPoint* points, size_t i) {
#if defined(__CUDA_ARCH__)
  const uint4* w = reinterpret_cast<const uint4*>(points + i);
  const uint4 a = __ldg(w), b = __ldg(w + 1), c = __ldg(w + 2), d = __ldg(w + 3);
  ShadingPoint sp;
  sp.position = Vec3(__uint_as_float(a.x), __uint_as_float(a.y), __uint_as_float(a.z));
  sp.ng = Vec3(__uint_as_float(a.w), __uint_as_float(b.x), __uint_as_float(b.y));
  sp.ns = Vec3(__uint_as_float(b.z), __uint_as_float(b.w), __uint_as_float(c.x));
  sp.wo = Vec3(__uint_as_float(c.y), __uint_as_float(c.z), __uint_as_float(c.w));
  sp.prim = d.x;
  sp.material = d.y;
  sp.cls = static_cast<MaterialClass>(d.z & 0xffu);  // little-endian: byte 56 is the word's low byte
  sp.front_face = ((d.z >> 8) & 0xffu) != 0u;
  sp.pad16 = static_cast<uint16_t>(d.z >> 16);
  sp.pad32 = d.w;
  return sp;
#else
  return points[i];
#endif
}

// points[i] = sp: on the device four 16-byte stores, on the host a plain copy.
RAYCOH_HD RAYCOH_INLINE void store_point(ShadingPoint* points, size_t i, const ShadingPoint& sp) {
#if defined(__CUDA_ARCH__)
  uint4* w = reinterpret_cast<uint4*>(points + i);
  w[0] = make_uint4(__float_as_uint(sp.position.x), __float_as_uint(sp.position.y), __float_as_uint(sp.position.z),
                    __float_as_uint(sp.ng.x));
  w[1] = make_uint4(__float_as_uint(sp.ng.y), __float_as_uint(sp.ng.z), __float_as_uint(sp.ns.x),
                    __float_as_uint(sp.ns.y));
  w[2] = make_uint4(__float_as_uint(sp.ns.z), __float_as_uint(sp.wo.x), __float_as_uint(sp.wo.y),
                    __float_as_uint(sp.wo.z));
  w[3] = make_uint4(sp.prim, sp.material,
                    uint32_t{static_cast<uint8_t>(sp.cls)} | (sp.front_face ? 0x100u : 0u) | (uint32_t{sp.pad16} << 16),
                    sp.pad32);
#else
  points[i] = sp;
#endif
}

}  // namespace raycoh
