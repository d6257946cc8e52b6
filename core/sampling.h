// BSDF sampling and frames shared by host and device.
//
// - Tangent frame from the normal only: the branchless ONB of Duff et al. ("Building an Orthonormal Basis,
//   Revisited", JCGT 2017), so parallel surfaces get identical frames. It flips at n.z = 0 (the sign of n.z
//   picks the branch): normals a hair apart on either side get frames far apart about the normal (the same
//   tangent-space direction up to ~130 deg apart; tests/hybrid_reuse_test.cpp).
// - rotate_between: the minimal rotation from one normal to another (the `ours:frame=rotate` reuse).
// - Cosine-weighted hemisphere sampling (Malley's method).
// - GGX visible-normal sampling (Heitz, "Sampling the GGX Distribution of Visible Normals", JCGT 2018),
//   isotropic, alpha = roughness^2 clamped to kMinAlpha so near-specular lobes keep a finite pdf.
// - Ray origin offsets against self-intersection (Waechter & Binder, Ray Tracing Gems ch. 6), which scale with
//   the magnitude of the position and so work for scenes far from the origin.
#pragma once

#include "core/vec.h"

namespace raycoh {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvPi = 0.31830988618379067154f;
constexpr float kMinAlpha = 1e-3f;

struct Frame {
  Vec3 t, b, n;
  RAYCOH_HD Vec3 to_local(Vec3 v) const { return {dot(v, t), dot(v, b), dot(v, n)}; }
  RAYCOH_HD Vec3 to_world(Vec3 v) const { return t * v.x + b * v.y + n * v.z; }
};

RAYCOH_HD RAYCOH_INLINE Frame make_frame(Vec3 n) {
  const float sign = copysignf(1.f, n.z);
  const float a = -1.f / (sign + n.z);
  const float b = n.x * n.y * a;
  Frame f;
  f.t = {1.f + sign * n.x * n.x * a, sign * b, -sign * n.x};
  f.b = {b, sign + n.y * n.y * a, -n.y};
  f.n = n;
  return f;
}

// The minimal rotation taking unit vector a to unit vector b (about the axis a x b), applied to v: Rodrigues'
// formula with k = a x b, c = a . b: v c + k x v + k (k . v) / (1 + c). Continuous in a and b wherever b is not
// near -a; a == b gives v exactly; b within ~0.8 deg of -a (1 + c < 1e-4, where 1 + c loses its precision) gives
// the half turn about make_frame(a).t, one of the equally minimal rotations. The result is renormalised.
RAYCOH_HD RAYCOH_INLINE Vec3 rotate_between(Vec3 a, Vec3 b, Vec3 v) {
  if (a.x == b.x && a.y == b.y && a.z == b.z) return v;
  const float c = dot(a, b);
  if (c < -1.f + 1e-4f) {
    const Vec3 u = make_frame(a).t;
    return normalize(u * (2.f * dot(u, v)) - v);
  }
  const Vec3 k = cross(a, b);
  return normalize(v * c + cross(k, v) + k * (dot(k, v) / (1.f + c)));
}

// sin and cos of 2 pi u, bit-identical on the CPU and the GPU: glibc's sinf/cosf and CUDA's differ in the last
// bits, so both sides evaluate the same polynomials with IEEE +, -, x only (no FMA contraction on either side:
// -ffp-contract=off, --fmad=false) and the exact floorf. The argument is reduced in turns to the nearest quarter
// q = floor(4u + 1/2), r = u - q/4 in [-1/8, 1/8] (exact for u in [0, 1): the subtraction meets Sterbenz's
// condition), then sin(2 pi r) = r (s1 + s3 r^2 + s5 r^4 + s7 r^6) and cos(2 pi r) = 1 + c2 r^2 + ... + c8 r^8,
// minimax for absolute error on |r| <= 0.12506 (Lawson's iteration, coefficients rounded to float), and the
// quadrant q mod 4 rotates (sin, cos). Measured over every u = k / 2^24 (all rng_float values): max absolute
// error 9.6e-8 for sin and cos, max |sin^2 + cos^2 - 1| 2.1e-7 (sinf(2 pi u) with the rounded float phase:
// 4.1e-7). Accurate for |u| < 2^20; callers pass u in [0, 1).
RAYCOH_HD RAYCOH_INLINE void sincos_turns(float u, float& s, float& c) {
  const float q = floorf(u * 4.f + 0.5f);
  const float r = u - q * 0.25f;
  const float r2 = r * r;
  const float sr = r * (6.28318501f + r2 * (-41.341629f + r2 * (81.588089f + r2 * -75.2386093f)));
  const float cr = 1.f + r2 * (-19.7392082f + r2 * (64.9393234f + r2 * (-85.443718f + r2 * 59.2449722f)));
  switch (static_cast<int>(q) & 3) {
    case 0:
      s = sr;
      c = cr;
      break;
    case 1:
      s = cr;
      c = -sr;
      break;
    case 2:
      s = -sr;
      c = -cr;
      break;
    default:
      s = -cr;
      c = sr;
      break;
  }
}

// Cosine-weighted direction around +z; pdf = z / pi.
RAYCOH_HD RAYCOH_INLINE Vec3 sample_cosine_hemisphere(float u1, float u2) {
  const float r = sqrtf(u1);
  float s, c;
  sincos_turns(u2, s, c);
  return {r * c, r * s, sqrtf(fmaxf(0.f, 1.f - u1))};
}

RAYCOH_HD RAYCOH_INLINE float cosine_pdf(Vec3 local_dir) { return fmaxf(local_dir.z, 0.f) * kInvPi; }

RAYCOH_HD RAYCOH_INLINE float ggx_alpha(float roughness) { return fmaxf(roughness * roughness, kMinAlpha); }

RAYCOH_HD RAYCOH_INLINE float ggx_d(Vec3 m, float alpha) {
  if (m.z <= 0.f) return 0.f;
  const float a2 = alpha * alpha;
  const float k = (m.x * m.x + m.y * m.y) / a2 + m.z * m.z;
  return 1.f / (kPi * a2 * k * k);
}

// Smith G1 for the isotropic GGX distribution, w in the local frame.
RAYCOH_HD RAYCOH_INLINE float ggx_g1(Vec3 w, float alpha) {
  if (w.z <= 0.f) return 0.f;
  const float tan2 = (w.x * w.x + w.y * w.y) / (w.z * w.z);
  return 2.f / (1.f + sqrtf(1.f + alpha * alpha * tan2));
}

// Visible normal for view direction wo (local frame, wo.z > 0).
RAYCOH_HD RAYCOH_INLINE Vec3 sample_ggx_vndf(Vec3 wo, float alpha, float u1, float u2) {
  const Vec3 vh = normalize(Vec3{alpha * wo.x, alpha * wo.y, wo.z});
  const float lensq = vh.x * vh.x + vh.y * vh.y;
  const Vec3 t1 = lensq > 0.f ? Vec3{-vh.y, vh.x, 0.f} * (1.f / sqrtf(lensq)) : Vec3{1.f, 0.f, 0.f};
  const Vec3 t2 = cross(vh, t1);
  const float r = sqrtf(u1);
  float s, c;
  sincos_turns(u2, s, c);
  const float p1 = r * c;
  const float sv = 0.5f * (1.f + vh.z);
  const float p2 = (1.f - sv) * sqrtf(fmaxf(0.f, 1.f - p1 * p1)) + sv * (r * s);
  const Vec3 nh = t1 * p1 + t2 * p2 + vh * sqrtf(fmaxf(0.f, 1.f - p1 * p1 - p2 * p2));
  return normalize(Vec3{alpha * nh.x, alpha * nh.y, fmaxf(1e-6f, nh.z)});
}

RAYCOH_HD RAYCOH_INLINE Vec3 reflect(Vec3 wo, Vec3 m) { return m * (2.f * dot(wo, m)) - wo; }

// pdf of the reflected direction wi when m is drawn from the visible normals of wo (local frame).
RAYCOH_HD RAYCOH_INLINE float ggx_reflection_pdf(Vec3 wo, Vec3 wi, float alpha) {
  if (wo.z <= 0.f || wi.z <= 0.f) return 0.f;
  Vec3 m = wo + wi;
  const float len2 = dot(m, m);
  if (!(len2 > 0.f)) return 0.f;
  m = m * (1.f / sqrtf(len2));
  return ggx_g1(wo, alpha) * ggx_d(m, alpha) / (4.f * wo.z);
}

// Schlick's Fresnel for a reflectance at normal incidence f0.
RAYCOH_HD RAYCOH_INLINE Vec3 fresnel_schlick(Vec3 f0, float cos_theta) {
  const float m = fminf(fmaxf(1.f - cos_theta, 0.f), 1.f);
  const float m5 = m * m * m * m * m;
  return f0 + (Vec3(1.f) - f0) * m5;
}

// Exact dielectric Fresnel reflectance for unpolarised light; cos_i > 0 on the side of the incident ray,
// eta = n_transmitted / n_incident. Returns 1 for total internal reflection.
RAYCOH_HD RAYCOH_INLINE float fresnel_dielectric(float cos_i, float eta) {
  const float sin2_t = (1.f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.f) return 1.f;
  const float cos_t = sqrtf(fmaxf(0.f, 1.f - sin2_t));
  const float rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const float rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5f * (rs * rs + rp * rp);
}

// Refraction of wo (pointing away from the surface, on the side of n) with eta = n_t / n_i; false on TIR.
RAYCOH_HD RAYCOH_INLINE bool refract(Vec3 wo, Vec3 n, float eta, Vec3& wt) {
  const float cos_i = dot(wo, n);
  const float sin2_t = (1.f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.f) return false;
  const float cos_t = sqrtf(fmaxf(0.f, 1.f - sin2_t));
  wt = (-wo) * (1.f / eta) + n * (cos_i / eta - cos_t);
  return true;
}

RAYCOH_HD RAYCOH_INLINE int32_t float_bits(float f) {
#if defined(__CUDA_ARCH__)
  return __float_as_int(f);
#else
  return __builtin_bit_cast(int32_t, f);
#endif
}
RAYCOH_HD RAYCOH_INLINE float bits_float(int32_t i) {
#if defined(__CUDA_ARCH__)
  return __int_as_float(i);
#else
  return __builtin_bit_cast(float, i);
#endif
}

// Move p off the surface along the geometric normal n (pointing to the side the new ray leaves on).
RAYCOH_HD RAYCOH_INLINE Vec3 offset_ray_origin(Vec3 p, Vec3 n) {
  const float origin = 1.f / 32.f, float_scale = 1.f / 65536.f, int_scale = 256.f;
  const int32_t ox = static_cast<int32_t>(int_scale * n.x), oy = static_cast<int32_t>(int_scale * n.y),
                oz = static_cast<int32_t>(int_scale * n.z);
  const Vec3 pi{bits_float(float_bits(p.x) + (p.x < 0.f ? -ox : ox)),
                bits_float(float_bits(p.y) + (p.y < 0.f ? -oy : oy)),
                bits_float(float_bits(p.z) + (p.z < 0.f ? -oz : oz))};
  return {fabsf(p.x) < origin ? p.x + float_scale * n.x : pi.x, fabsf(p.y) < origin ? p.y + float_scale * n.y : pi.y,
          fabsf(p.z) < origin ? p.z + float_scale * n.z : pi.z};
}

}  // namespace raycoh
