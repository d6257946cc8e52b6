// Turning a shading point and the direction chosen for it into the batch's ray, shared by the CPU generators
// and the CUDA ones. The origin is offset along the geometric normal on the side the direction leaves
// (Waechter & Binder); a non-finite position or normal yields a finite stand-in ray with weight 0, flagged
// kSampleNonFinite.
#pragma once

#include "core/bsdf.h"
#include "core/ray.h"

namespace raycoh {

struct SecondaryRay {
  Ray ray;
  Vec3 weight;
  Vec3 normal;  // shading normal at the origin (the direction when the normal is not finite)
  uint32_t flags = kSampleOk;
};

RAYCOH_HD RAYCOH_INLINE SecondaryRay make_secondary_ray(Vec3 position, Vec3 ng, Vec3 ns, const DirectionSample& s) {
  SecondaryRay out;
  out.flags = s.flags;
  if (is_finite(position) && is_finite(ng)) {
    out.ray.org = offset_ray_origin(position, dot(s.dir, ng) >= 0.f ? ng : -ng);
    out.weight = s.weight;
  } else {
    out.ray.org = Vec3(0.f);
    out.weight = Vec3(0.f);
    out.flags |= kSampleNonFinite;
  }
  out.ray.dir = s.dir;
  out.ray.tmin = 0.f;
  out.ray.tmax = __builtin_huge_valf();
  out.normal = is_finite(ns) ? ns : s.dir;
  return out;
}

}  // namespace raycoh
