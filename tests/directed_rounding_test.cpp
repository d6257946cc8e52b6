// core/directed_rounding.h on the host: each result is the float at or below (down) / at or above (up) the exact
// value, and the nearest such float, checked against the exact value in quadruple precision (__float128 holds a
// float product and sum exactly for the exponent ranges drawn here).
#include "core/directed_rounding.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>

namespace raycoh {
namespace {

using Quad = __float128;

void expect_brackets(float down, float up, Quad exact, const char* what, int i) {
  ASSERT_LE(static_cast<Quad>(down), exact) << what << " #" << i;
  ASSERT_GE(static_cast<Quad>(up), exact) << what << " #" << i;
  // Tight: the next float beyond each bound passes the exact value.
  ASSERT_GT(static_cast<Quad>(std::nextafter(down, __builtin_huge_valf())), exact) << what << " #" << i;
  ASSERT_LT(static_cast<Quad>(std::nextafter(up, -__builtin_huge_valf())), exact) << what << " #" << i;
  if (static_cast<Quad>(down) == exact) {
    ASSERT_EQ(down, up) << what << " #" << i;
  }
}

float random_float(std::mt19937& rng, int min_exp, int max_exp) {
  std::uniform_real_distribution<float> mant(1.f, 2.f);
  std::uniform_int_distribution<int> ex(min_exp, max_exp), sign(0, 1);
  return std::ldexp(mant(rng), ex(rng)) * (sign(rng) ? -1.f : 1.f);
}

TEST(DirectedRounding, EachResultIsTheNearestFloatOnItsSide) {
  std::mt19937 rng(7);
  for (int i = 0; i < 200000; ++i) {
    const float a = random_float(rng, -20, 20), b = random_float(rng, -20, 20), c = random_float(rng, -30, 30);
    expect_brackets(fma_down(a, b, c), fma_up(a, b, c), Quad(a) * Quad(b) + Quad(c), "fma", i);
    expect_brackets(sub_down(a, c), sub_up(a, c), Quad(a) - Quad(c), "sub", i);
    expect_brackets(mul_down(a, b), mul_up(a, b), Quad(a) * Quad(b), "mul", i);
    // The CWBVH's case: an 8-bit q times a power of two plus a float.
    const float q = static_cast<float>(rng() % 256), scale = std::ldexp(1.f, static_cast<int>(rng() % 40) - 20);
    expect_brackets(fma_down(q, scale, c), fma_up(q, scale, c), Quad(q) * Quad(scale) + Quad(c), "decode", i);
  }
}

TEST(DirectedRounding, ExactResultsAndCancellation) {
  EXPECT_EQ(fma_down(3.f, 0.5f, 1.f), 2.5f);
  EXPECT_EQ(fma_up(3.f, 0.5f, 1.f), 2.5f);
  EXPECT_EQ(sub_down(1.f, 1.f), 0.f);
  EXPECT_EQ(sub_up(1.f, 1.f), 0.f);
  // 1 + 2^-30: between 1 and the next float.
  EXPECT_EQ(fma_down(1.f, std::ldexp(1.f, -30), 1.f), 1.f);
  EXPECT_EQ(fma_up(1.f, std::ldexp(1.f, -30), 1.f), std::nextafter(1.f, 2.f));
  // A tiny remainder far below the sum's ulp still decides the direction (TwoSum keeps it).
  EXPECT_EQ(sub_up(1.f, std::ldexp(1.f, -60)), 1.f);
  EXPECT_EQ(sub_down(1.f, std::ldexp(1.f, -60)), std::nextafter(1.f, 0.f));
  // Beyond the float range: +inf upwards, FLT_MAX downwards.
  EXPECT_EQ(mul_up(3e38f, 2.f), __builtin_huge_valf());
  EXPECT_EQ(mul_down(3e38f, 2.f), 3.40282347e38f);
  // Subnormal results flush to zero, as the device's -ftz=true does.
  EXPECT_EQ(mul_up(1e-30f, 1e-10f), 0.f);
  EXPECT_EQ(mul_down(-1e-30f, 1e-10f), 0.f);
  EXPECT_TRUE(std::signbit(mul_down(-1e-30f, 1e-10f)));
}

}  // namespace
}  // namespace raycoh
