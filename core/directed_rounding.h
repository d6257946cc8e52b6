// Float arithmetic rounded towards -inf ("down") or +inf ("up"), bit-identical on host and device, for tests that
// must stay conservative (the CWBVH node step, core/traverse_cwbvh.h): on the device the rounding-mode intrinsics
// (one instruction each: FFMA.RM, FADD.RP, ...); on the host the exact result, from double arithmetic whose own
// rounding error is recovered exactly (Knuth's TwoSum; a product of two floats is exact in a double), then the
// float at or below (above) it. Both flush subnormal results to a zero of the same sign, as the device's -ftz=true
// does. Inputs are finite normal floats or zeros; results beyond the float range become +-inf or +-FLT_MAX as
// the rounding direction gives.
#pragma once

#include "core/platform.h"

#if !defined(__CUDA_ARCH__)
#include <cmath>
#include <cstdint>
#endif

namespace raycoh {

#if !defined(__CUDA_ARCH__)
namespace directed_detail {

inline float flush(float f) { return std::fabs(f) < 1.17549435e-38f ? std::copysign(0.f, f) : f; }

// The largest float <= s + e (down) or the smallest >= s + e (up), where s + e is exact and |e| <= ulp(s) / 2.
inline float round_to_float(double s, double e, bool up) {
  float f = static_cast<float>(s);  // nearest
  const double fd = f;
  if (up ? (fd < s || (fd == s && e > 0)) : (fd > s || (fd == s && e < 0)))
    f = std::nextafter(f, up ? __builtin_huge_valf() : -__builtin_huge_valf());
  return flush(f);
}

// s + e == a + b exactly (Knuth's TwoSum).
inline void two_sum(double a, double b, double& s, double& e) {
  s = a + b;
  const double bb = s - a;
  e = (a - (s - bb)) + (b - bb);
}

inline float fma_dir(float a, float b, float c, bool up) {
  double s, e;
  two_sum(static_cast<double>(a) * static_cast<double>(b), c, s, e);  // the product is exact
  return round_to_float(s, e, up);
}

}  // namespace directed_detail
#endif

// a * b + c, one rounding.
RAYCOH_HD RAYCOH_INLINE float fma_down(float a, float b, float c) {
#if defined(__CUDA_ARCH__)
  return __fmaf_rd(a, b, c);
#else
  return directed_detail::fma_dir(a, b, c, false);
#endif
}
RAYCOH_HD RAYCOH_INLINE float fma_up(float a, float b, float c) {
#if defined(__CUDA_ARCH__)
  return __fmaf_ru(a, b, c);
#else
  return directed_detail::fma_dir(a, b, c, true);
#endif
}
RAYCOH_HD RAYCOH_INLINE float sub_down(float a, float b) {
#if defined(__CUDA_ARCH__)
  return __fsub_rd(a, b);
#else
  return directed_detail::fma_dir(1.f, a, -b, false);
#endif
}
RAYCOH_HD RAYCOH_INLINE float sub_up(float a, float b) {
#if defined(__CUDA_ARCH__)
  return __fsub_ru(a, b);
#else
  return directed_detail::fma_dir(1.f, a, -b, true);
#endif
}
RAYCOH_HD RAYCOH_INLINE float mul_down(float a, float b) {
#if defined(__CUDA_ARCH__)
  return __fmul_rd(a, b);
#else
  return directed_detail::fma_dir(a, b, 0.f, false);
#endif
}
RAYCOH_HD RAYCOH_INLINE float mul_up(float a, float b) {
#if defined(__CUDA_ARCH__)
  return __fmul_ru(a, b);
#else
  return directed_detail::fma_dir(a, b, 0.f, true);
#endif
}

}  // namespace raycoh
