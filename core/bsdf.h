// First-bounce direction sampling for one shading point, shared by the generators (and later the path tracer
// and the CUDA generators). Lobes:
//   diffuse, emissive  Lambert, cosine-weighted, weight = base colour
//   glossy, specular   GGX reflection via visible normals, alpha = roughness^2 (>= kMinAlpha),
//                      F0 = lerp(0.04, base colour, metallic), weight = F(wo.m) G1(wi)  (f cos / pdf for VNDF)
//   transmissive       smooth dielectric: reflect with probability F (weight 1), else refract (thin-walled:
//                      pass straight through) with weight = base colour; pdf = the discrete probability
// Every sample is checked against the geometric surface: a reflected direction must leave on the geometric
// normal's side, a transmitted one on the other. Violations are kept in the batch (the ray count stays one per
// hit pixel) but get weight 0 and a flag, as do NaN/Inf directions, which are replaced by the geometric normal.
#pragma once

#include "core/material.h"
#include "core/sampling.h"

namespace raycoh {

enum SampleFlags : uint32_t {
  kSampleOk = 0,
  kSampleBelowShading = 1u << 0,    // glossy reflection fell below the shading hemisphere
  kSampleBelowGeometric = 1u << 1,  // direction on the wrong side of the geometric surface
  kSampleNonFinite = 1u << 2,
  kSampleTransmitted = 1u << 3,  // refraction lobe chosen
};

struct DirectionSample {
  Vec3 dir;
  float pdf = 0.f;
  Vec3 weight;
  uint32_t flags = kSampleOk;
};

// Shading frame inputs: ns and ng unit and in the same hemisphere, wo unit with dot(wo, ng) >= 0.
RAYCOH_HD RAYCOH_INLINE Vec3 shading_wo_local(const Frame& f, Vec3 wo) {
  Vec3 w = f.to_local(wo);
  // wo can be below the shading hemisphere when ns differs from ng: lift it just above so sampling is defined.
  if (!(w.z > 1e-4f)) w = normalize(Vec3{w.x, w.y, 1e-4f});
  return w;
}

// Checks the side of the geometric surface and finiteness; sets flags and zeroes the weight when rejected.
RAYCOH_HD RAYCOH_INLINE void check_direction(DirectionSample& s, Vec3 ng) {
  if (!is_finite(s.dir) || !(dot(s.dir, s.dir) > 0.f) || !is_finite(s.pdf) || !is_finite(ng)) {
    s.dir = is_finite(ng) && dot(ng, ng) > 0.f ? ng : Vec3{0.f, 0.f, 1.f};
    s.pdf = 0.f;
    s.weight = Vec3(0.f);
    s.flags |= kSampleNonFinite;
    return;
  }
  const bool transmitted = (s.flags & kSampleTransmitted) != 0;
  const float side = dot(s.dir, ng);
  if (transmitted ? !(side < 0.f) : !(side > 0.f)) {
    s.weight = Vec3(0.f);
    s.flags |= kSampleBelowGeometric;
  }
}

// A Lambertian member using the tangent-space direction `local` (z > 0) in its own frame: pdf and weight by
// its own BSDF (cos / pi and the base colour), then the geometric-side check. Exactly what sample_direction()
// does for a diffuse point, so sharing the donor's own sample reproduces NoOpt bit for bit.
RAYCOH_HD RAYCOH_INLINE DirectionSample diffuse_from_local(const BsdfParams& m, Vec3 ns, Vec3 ng, Vec3 local) {
  DirectionSample s;
  const Frame f = make_frame(ns);
  s.dir = f.to_world(local);
  s.pdf = cosine_pdf(local);
  s.weight = m.base_color;
  check_direction(s, ng);
  return s;
}

// The same for a world direction wi carried to this member (the `ours:frame=rotate` reuse): pdf cos / pi with
// cos = wi . ns, weight the base colour (0, flagged below_shading, when wi is not above the shading surface).
RAYCOH_HD RAYCOH_INLINE DirectionSample diffuse_from_world(const BsdfParams& m, Vec3 ns, Vec3 ng, Vec3 wi) {
  DirectionSample s;
  s.dir = wi;
  s.pdf = fmaxf(dot(wi, ns), 0.f) * kInvPi;
  s.weight = s.pdf > 0.f ? m.base_color : Vec3(0.f);
  if (!(s.pdf > 0.f)) s.flags |= kSampleBelowShading;
  check_direction(s, ng);
  return s;
}

// pdf and weight of using the world direction wi at this point, by the material's own BSDF (used when a
// direction is chosen elsewhere, e.g. shared in a group). Non-delta lobes only (diffuse, glossy, specular).
RAYCOH_HD RAYCOH_INLINE DirectionSample evaluate_direction(const BsdfParams& m, Vec3 ns, Vec3 ng, Vec3 wo, Vec3 wi) {
  DirectionSample s;
  s.dir = wi;
  const Frame f = make_frame(ns);
  const Vec3 li = f.to_local(wi);
  if (m.cls == MaterialClass::Glossy || m.cls == MaterialClass::Specular) {
    const float alpha = ggx_alpha(m.roughness);
    const Vec3 lo = shading_wo_local(f, wo);
    s.pdf = ggx_reflection_pdf(lo, li, alpha);
    if (s.pdf > 0.f) {
      const Vec3 h = normalize(lo + li);
      const Vec3 f0 = Vec3(0.04f) * (1.f - m.metallic) + m.base_color * m.metallic;
      s.weight = fresnel_schlick(f0, dot(lo, h)) * ggx_g1(li, alpha);
    } else {
      s.weight = Vec3(0.f);
      s.flags |= kSampleBelowShading;
    }
  } else {
    s.pdf = cosine_pdf(li);
    s.weight = s.pdf > 0.f ? m.base_color : Vec3(0.f);
    if (!(s.pdf > 0.f)) s.flags |= kSampleBelowShading;
  }
  check_direction(s, ng);
  return s;
}

// Samples the material's own lobe with three uniform numbers (u0, u1: direction; u2: lobe choice).
RAYCOH_HD RAYCOH_INLINE DirectionSample sample_direction(const BsdfParams& m, Vec3 ns, Vec3 ng, Vec3 wo,
                                                         bool front_face, float u0, float u1, float u2) {
  DirectionSample s;
  const Frame f = make_frame(ns);
  switch (m.cls) {
    case MaterialClass::Glossy:
    case MaterialClass::Specular: {
      const float alpha = ggx_alpha(m.roughness);
      const Vec3 lo = shading_wo_local(f, wo);
      const Vec3 mh = sample_ggx_vndf(lo, alpha, u0, u1);
      const Vec3 li = reflect(lo, mh);
      s.dir = f.to_world(li);
      s.pdf = ggx_reflection_pdf(lo, li, alpha);
      if (li.z > 0.f && s.pdf > 0.f) {
        const Vec3 f0 = Vec3(0.04f) * (1.f - m.metallic) + m.base_color * m.metallic;
        s.weight = fresnel_schlick(f0, dot(lo, mh)) * ggx_g1(li, alpha);
      } else {
        s.weight = Vec3(0.f);
        s.flags |= kSampleBelowShading;
      }
      break;
    }
    case MaterialClass::Transmissive: {
      // Smooth dielectric around the shading normal; eta = n_inside / n_outside when entering.
      const float eta = m.thin_walled ? 1.f : (front_face ? m.ior : 1.f / m.ior);
      const float cos_i = fminf(fmaxf(dot(wo, ns), 0.f), 1.f);
      const float fr = fresnel_dielectric(cos_i, m.thin_walled ? m.ior : eta);
      Vec3 wt;
      if (u2 < fr || !refract(wo, ns, eta, wt)) {
        s.dir = reflect(wo, ns);
        s.pdf = fr;
        s.weight = Vec3(1.f);
      } else {
        s.dir = wt;
        s.pdf = 1.f - fr;
        s.weight = m.base_color;
        s.flags |= kSampleTransmitted;
      }
      break;
    }
    default:  // diffuse and emissive surfaces reflect diffusely
      return diffuse_from_local(m, ns, ng, sample_cosine_hemisphere(u0, u1));
  }
  check_direction(s, ng);
  return s;
}

}  // namespace raycoh
