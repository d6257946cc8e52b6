// Rays and hits as the tracers see them (host and device).
#pragma once

#include "core/vec.h"

namespace raycoh {

// 32 bytes: one ray of a batch, in the layout every tracer reads.
struct Ray {
  Vec3 org;
  float tmin = 0.f;
  Vec3 dir;
  float tmax = __builtin_huge_valf();
};
static_assert(sizeof(Ray) == 32, "Ray is two 16-byte words");

constexpr uint32_t kNoHit = 0xFFFFFFFFu;

// Closest hit: t, primitive (triangle) id in the scene's order, and barycentrics with the convention
// p = (1 - u - v) v0 + u v1 + v v2 (the same as Embree's).
struct Hit {
  float t = __builtin_huge_valf();
  uint32_t prim = kNoHit;
  float u = 0.f, v = 0.f;
  RAYCOH_HD bool valid() const { return prim != kNoHit; }
};
static_assert(sizeof(Hit) == 16, "Hit is one 16-byte word");

}  // namespace raycoh
