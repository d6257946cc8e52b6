// The sRGB decode (IEC 61966-2-1: c / 12.92 for c <= 0.04045, else ((c + 0.055) / 1.055)^2.4), bit-identical on
// the CPU and the GPU: glibc's powf and CUDA's round some arguments 1 ulp apart, and a textured hit's base colour
// picks the first bounce's lobe, so both sides evaluate the same table and polynomial with IEEE +, -, x only (no
// FMA contraction on either side: -ffp-contract=off, --fmad=false) and the exact frexpf / ldexpf, as sincos_turns
// does (core/sampling.h). The linear segment is c x (1 / 12.92f), as before.
//
// ((c + 0.055) / 1.055)^2.4 = 1.055^-2.4 s^2.4 with s = c + 0.055, so the division's rounding never reaches the
// power: s is kept as s_hi + s_lo (Knuth's TwoSum of c and 0.055f, exact, plus 0.055's own rounding error), and
// s_hi = m 2^E with m in [1, 2) (frexpf, exact). m lies in one of 16 intervals [1 + j/16, 1 + (j+1)/16) of centre
// m0 = 1 + (j + 1/2)/16; t = m - m0 is exact, s_lo 2^-E is added to it, and u = t x (1/m0 rounded), |u| <= 1/33.
// With E = 5q + r (r in 0..4), 2^(2.4 E) = 2^(2E + 2q) 2^(0.4 r), so
//   linear = 2^(2E + 2q) T(r, j) (1 + u)^2.4,   T(r, j) = 1.055^-2.4 2^(0.4 r) m0^2.4,
// with T held as a float pair hi + lo (80 pairs, computed in 200-bit arithmetic, each checked by the test below), (1 +
// u)^2.4 - 1 = p(u) = u (2.4 + u (1.68 + u (0.224 - 0.0336 u))) (its Taylor series to u^4; the u^5 term is below
// 3e-10), the sum hi + (lo + hi p) rounded once, then scaled by 2^(2E + 2q) (ldexpf, exact for normal results).
//
// Measured (tests/surface_textures_test.cpp: every float c in [0.03, 1.0001] and every 64th below, against the
// formula in double): max error 0.78 ulp on the power segment, 0.56 ulp on the linear one; non-decreasing. The
// former powf((c + 0.055f) x (1 / 1.055f), 2.4f), whose argument is rounded twice, was up to 6.7 ulp off (glibc).
//
// Inputs: any float; NaN and c <= 0.04045 take the linear segment, +inf gives +inf, and every finite c above
// 0.04045 the power (texels filtered from 8 bits lie in [0, 1], a rounding above 1 at most).
#pragma once

#include "core/platform.h"

#if !defined(__CUDA_ARCH__)
#include <cmath>
#endif

namespace raycoh {

// T(r, j) = hi[16 r + j] + lo[16 r + j]; recip[j] = 1 / m0_j rounded.
struct SrgbPowTable {
  float hi[80];
  float lo[80];
  float recip[16];
};

// One table for both sides: a function-local constant (device code: a __device__ variable of its own).
RAYCOH_HD RAYCOH_INLINE const SrgbPowTable& srgb_pow_table() {
  static constexpr SrgbPowTable kTable = {
      {
          0.946820378f, 1.09042919f, 1.24600065f, 1.41380405f, 1.5940994f,  1.78713942f, 1.99316931f, 2.21242738f,
          2.44514561f,  2.69155073f, 2.95186329f, 3.22629881f, 3.51506853f, 3.81837845f, 4.13643074f, 4.46942329f,
          1.24933696f,  1.4388299f,  1.64410782f, 1.8655256f,  2.10342669f, 2.35814476f, 2.6300025f,  2.91931534f,
          3.22638917f,  3.55152249f, 3.8950069f,  4.25712681f, 4.63816071f, 5.03838062f, 5.45805311f, 5.897439f,
          1.6485101f,   1.89854741f, 2.16941333f, 2.46157575f, 2.77548838f, 3.11159062f, 3.47030926f, 3.8520596f,
          4.25724602f,  4.68626213f, 5.13949251f, 5.61731291f, 6.12009001f, 6.64818335f, 7.20194435f, 7.78171778f,
          2.17522216f,  2.50514841f, 2.86255789f, 3.24806857f, 3.66227889f, 4.1057682f,  4.57910061f, 5.08282328f,
          5.61746979f,  6.18355989f, 6.78160095f, 7.41208839f, 8.07550716f, 8.77233028f, 9.50302219f, 10.2680378f,
          2.87022281f,  3.30556297f, 3.7771678f,  4.28585243f, 4.83240604f, 5.41759396f, 6.04215956f, 6.70682526f,
          7.41229582f,  8.15925598f, 8.9483757f,  9.78030968f, 10.655695f,  11.5751591f, 12.5393133f, 13.5487576f,
      },
      {
          1.74227832e-08f,  -3.04133572e-08f, 5.34976259e-08f,  -5.51660335e-08f, 2.22398366e-08f,  3.670932e-08f,
          -4.12663184e-08f, -8.17838384e-08f, 8.31403852e-08f,  9.44269107e-09f,  -2.69567888e-08f, 1.17918958e-07f,
          4.79633897e-08f,  5.90131357e-08f,  -3.84726455e-08f, -2.11501344e-07f, 4.43104717e-08f,  -8.16951784e-10f,
          -3.67493804e-08f, -4.22071977e-08f, 1.06537307e-07f,  -1.14969346e-07f, 1.15953476e-07f,  -1.91624441e-08f,
          -8.85675959e-08f, 1.76781556e-09f,  3.0561452e-08f,   1.48489136e-07f,  9.13330211e-08f,  2.41069706e-08f,
          -7.85304834e-08f, 1.11046134e-07f,  -4.07777385e-08f, 2.17253877e-08f,  -1.03850972e-07f, -1.0932685e-08f,
          -7.24287759e-08f, -1.09816945e-07f, -2.21537921e-09f, 5.4687046e-08f,   -1.01679802e-07f, -1.0312506e-07f,
          -6.08695458e-08f, -2.11700964e-07f, -1.44836477e-07f, -2.24631734e-07f, -1.96075646e-07f, -2.12979074e-07f,
          -9.63350999e-08f, -5.43846284e-08f, 2.31943105e-08f,  8.5004821e-08f,   -1.16975166e-07f, 9.46245393e-08f,
          -9.36395708e-08f, -8.57790567e-08f, -1.23625298e-07f, -7.71727926e-08f, -5.85507864e-09f, 1.46114317e-07f,
          -1.75203866e-07f, -6.34773158e-08f, 9.17176095e-08f,  8.94382524e-08f,  -8.83059386e-08f, 1.00923536e-07f,
          1.1818714e-08f,   -1.45799461e-07f, -2.30739872e-07f, -2.0650721e-07f,  -2.03330217e-07f, 1.52894643e-07f,
          -1.58190574e-07f, 1.14336835e-07f,  3.9443475e-07f,   -2.12876301e-07f, 3.93672366e-07f,  4.91723959e-08f,
          -2.34210205e-07f, -3.35121968e-07f,
      },
      {
          0.969696999f,
          0.914285719f,
          0.864864886f,
          0.820512831f,
          0.780487776f,
          0.744186044f,
          0.711111128f,
          0.680851042f,
          0.653061211f,
          0.627451003f,
          0.603773594f,
          0.581818163f,
          0.561403513f,
          0.542372882f,
          0.524590135f,
          0.507936537f,
      }};
  return kTable;
}

// The part of 0.055 that 0.055f leaves out.
constexpr float kSrgbOffsetLow = 2.98023217e-10f;

RAYCOH_HD RAYCOH_INLINE float srgb_to_linear(float c) {
  if (!(c > 0.04045f)) return c * (1.f / 12.92f);
  if (!(c <= 3.40282347e38f)) return c;  // +inf
  const SrgbPowTable& tab = srgb_pow_table();
  const float s = c + 0.055f;  // s + s_lo = c + 0.055
  const float bb = s - c;
  const float s_lo = ((c - (s - bb)) + (0.055f - bb)) + kSrgbOffsetLow;
  int e;
  const float m = 2.f * frexpf(s, &e);  // s = m 2^E, m in [1, 2)
  const int big_e = e - 1;
  const int j = static_cast<int>((m - 1.f) * 16.f);
  const float t = (m - (1.03125f + 0.0625f * static_cast<float>(j))) + ldexpf(s_lo, -big_e);
  const float u = t * tab.recip[j];
  const float p = u * (2.4f + u * (1.68f + u * (0.224f + u * -0.0336f)));
  int r = big_e % 5;
  if (r < 0) r += 5;
  const int k = 16 * r + j;
  const float y = tab.hi[k] + (tab.lo[k] + tab.hi[k] * p);
  return ldexpf(y, 2 * big_e + 2 * ((big_e - r) / 5));
}

}  // namespace raycoh
