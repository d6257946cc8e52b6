// The key building blocks of encoders/keys.h (quantisation, bit spreading, spherical coordinates) against the
// slow bit-by-bit reference, and literal codes worked out by hand for simple rays, directly and through
// make_encoder (a 32-bit key is the 64-bit code's top half).
#include "encoders/keys.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "encoders/encoder.h"
#include "tests/encoder_test_util.h"
#include "tests/key_reference.h"

namespace raycoh {
namespace {

using test::bit;
using test::box_of;
using test::keys_of;
using test::kInf;
using test::kNaN;
using test::kUnitBox;
using test::make_batch;
using test::push_level;
using test::random_unit;
using test::ray;
using test::ref_phi;
using test::ref_quantize;
using test::ref_theta;
using test::RefBits;
using test::RefQ;
using test::tiny_bvh;

// ---- building blocks ----------------------------------------------------------------------------------------

TEST(Keys, QuantisationFollowsTheRecipe) {
  EXPECT_EQ(quantize_coordinate(0.f, 0.f, 1.f, 21), 0u);
  EXPECT_EQ(quantize_coordinate(0.5f, 0.f, 1.f, 21), 1u << 20);
  EXPECT_EQ(quantize_coordinate(1.f, 0.f, 1.f, 21), (1u << 21) - 1);  // max face: clamped to 2^b - 1
  EXPECT_EQ(quantize_coordinate(8.f, 0.f, 8.f, 13), (1u << 13) - 1);
  EXPECT_EQ(quantize_coordinate(std::nextafter(1.f, 0.f), 0.f, 1.f, 21), (1u << 21) - 1);
  EXPECT_EQ(quantize_coordinate(-5.f, 0.f, 1.f, 21), 0u);  // outside: clamped
  EXPECT_EQ(quantize_coordinate(5.f, 0.f, 1.f, 21), (1u << 21) - 1);
  EXPECT_EQ(quantize_coordinate(3.f, 2.f, 2.f, 21), 0u);  // zero extent
  EXPECT_EQ(quantize_coordinate(kNaN, 0.f, 1.f, 21), 0u);
  EXPECT_EQ(quantize_coordinate(kInf, 0.f, 1.f, 21), (1u << 21) - 1);
  EXPECT_EQ(quantize_coordinate(-kInf, 0.f, 1.f, 21), 0u);
  EXPECT_EQ(quantize_coordinate(0.5f, kNaN, 1.f, 21), 0u);  // broken box: everything to 0
  EXPECT_EQ(quantize_coordinate(0.5f, -kInf, kInf, 21), 0u);
  EXPECT_EQ(quantize_coordinate(0.5f, kInf, -kInf, 21), 0u);  // empty box
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-3.f, 5.f);
  for (int i = 0; i < 20000; ++i) {
    const float p = u(rng);
    for (int b : {4, 13, 15, 21}) ASSERT_EQ(quantize_coordinate(p, -1.f, 3.f, b), ref_quantize(p, -1.f, 3.f, b));
  }
}

TEST(Keys, BitSpreadingMatchesBitByBitInterleaving) {
  std::mt19937 rng(11);
  for (int i = 0; i < 20000; ++i) {
    const RefQ q{{static_cast<uint32_t>(rng()) & 0x1FFFFF, static_cast<uint32_t>(rng()) & 0x1FFFFF,
                  static_cast<uint32_t>(rng()) & 0x1FFFFF}};
    RefBits r;
    r.push(0, 1);  // morton3 is 63 bits wide: right-aligned
    for (int l = 20; l >= 0; --l) push_level(r, q, l);
    ASSERT_EQ(morton3({q.v[0], q.v[1], q.v[2]}), r.code());
    const uint32_t a = static_cast<uint32_t>(rng()), b = static_cast<uint32_t>(rng());
    RefBits r2;
    for (int l = 31; l >= 0; --l) {
      r2.push(bit(a, l), 1);
      r2.push(bit(b, l), 1);
    }
    ASSERT_EQ(morton2(a, b), r2.code());
  }
  EXPECT_EQ(key_from_code(0x0123456789ABCDEFull, 32), 0x01234567ull);
  EXPECT_EQ(key_from_code(0x0123456789ABCDEFull, 64), 0x0123456789ABCDEFull);
}

TEST(Keys, SphericalCoordinatesOfTheAxes) {
  constexpr uint32_t half = 1u << 20, top = (1u << 21) - 1;
  struct Case {
    Vec3 d;
    uint32_t phi, theta;
  };
  for (const Case& c : std::vector<Case>{{{1, 0, 0}, half, half},
                                         {{-1, 0, 0}, top, half},     // seam: phi = 1
                                         {{-1, -0.f, 0}, top, half},  // -0 is read as +0
                                         {{0, 1, 0}, 3u << 19, half},
                                         {{0, -1, 0}, 1u << 19, half},
                                         {{0, 0, 1}, half, 0},  // poles: phi = 0.5
                                         {{0, 0, -1}, half, top},
                                         {{-0.f, -0.f, 1}, half, 0},
                                         {{0, 0, 2}, half, 0},  // clamped before acos
                                         {{kNaN, 0, kNaN}, 0, 0}}) {
    EXPECT_EQ(quantize_unit(spherical_phi(c.d), 21), c.phi) << c.d.x << " " << c.d.y << " " << c.d.z;
    EXPECT_EQ(quantize_unit(spherical_theta(c.d), 21), c.theta) << c.d.x << " " << c.d.y << " " << c.d.z;
  }
}

// atan2f/acosf may differ from the exact angle by an ulp: the quantised angle is within one step of the one
// computed in double, and equal to the float recipe's.
TEST(Keys, SphericalQuantisationIsWithinOneStepOfExact) {
  std::mt19937 rng(3);
  int exact = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const Vec3 d = random_unit(rng);
    const uint32_t phi = quantize_unit(spherical_phi(d), 21), theta = quantize_unit(spherical_theta(d), 21);
    ASSERT_EQ(phi, ref_phi(d, 21));
    ASSERT_EQ(theta, ref_theta(d, 21));
    const double dphi = std::atan2(double(d.y), double(d.x)) / (2.0 * M_PI) + 0.5;
    const double dtheta = std::acos(std::clamp(double(d.z), -1.0, 1.0)) / M_PI;
    const auto qphi = static_cast<int64_t>(std::min(std::floor(dphi * (1 << 21)), double((1 << 21) - 1)));
    const auto qtheta = static_cast<int64_t>(std::min(std::floor(dtheta * (1 << 21)), double((1 << 21) - 1)));
    ASSERT_LE(std::abs(int64_t{phi} - qphi), 1);
    ASSERT_LE(std::abs(int64_t{theta} - qtheta), 1);
    exact += (phi == qphi) && (theta == qtheta);
  }
  EXPECT_GT(exact, n * 8 / 10);
}

// ---- literal codes worked out by hand -------------------------------------------------------------------------

TEST(Keys, HandComputedOriginCodes) {
  EXPECT_EQ(origin_code({0, 0, 0}, kUnitBox), 0ull);
  EXPECT_EQ(origin_code({1, 1, 1}, kUnitBox), 0xFFFFFFFFFFFFFFFEull);  // max corner: all 63 bits
  EXPECT_EQ(origin_code({0.5f, 0, 0}, kUnitBox), 0x8000000000000000ull);
  EXPECT_EQ(origin_code({0, 0.5f, 0}, kUnitBox), 0x4000000000000000ull);
  EXPECT_EQ(origin_code({0, 0, 0.5f}, kUnitBox), 0x2000000000000000ull);
  // x = 0b11 << 19, y = 0b01 << 19: levels 20 and 19 are 100 and 110.
  EXPECT_EQ(origin_code({0.75f, 0.25f, 0}, kUnitBox), 0x9800000000000000ull);
  // Zero-extent y axis maps to 0: x and z at the max face give 101 on every level.
  EXPECT_EQ(origin_code({1, 2, 1}, box_of({0, 2, 0}, {1, 2, 1})), 0xB6DB6DB6DB6DB6DAull);
}

TEST(Keys, HandComputedReisCodes) {
  const Vec3 c{0.5f, 0.5f, 0.5f};  // origin level 20 = 111: the top 22 bits are 0xE0000 << 42
  EXPECT_EQ(reis_code(c, {1, 0, 0}, kUnitBox), 0xE000030000000000ull);  // phi = theta = 2^20: bits 41, 40
  const Vec3 o{0, 0, 0};
  EXPECT_EQ(reis_code(o, {0, 0, 1}, kUnitBox), 0x0000020000000000ull);   // phi 2^20, theta 0
  EXPECT_EQ(reis_code(o, {0, 0, -1}, kUnitBox), 0x0000035555555555ull);  // theta = 2^21 - 1
  EXPECT_EQ(reis_code(o, {-1, 0, 0}, kUnitBox), 0x000003AAAAAAAAAAull);  // phi = 2^21 - 1, theta 2^20
  EXPECT_EQ(reis_code(o, {0, 1, 0}, kUnitBox), 0x0000038000000000ull);   // phi = 3 << 19
  EXPECT_EQ(reis_code(o, {0, -1, 0}, kUnitBox), 0x0000018000000000ull);  // phi = 1 << 19
}

TEST(Keys, HandComputedCostaAilaAndTwoPointCodes) {
  const Vec3 c{0.5f, 0.5f, 0.5f};
  // phi4 = theta4 = 8 -> 11000000; origin 15-bit level 14 = 111 at bits 55..53.
  EXPECT_EQ(costa_code(c, {1, 0, 0}, kUnitBox), 0xC0E0000000000000ull);
  // Origin level 12 = 111 (bits 63..61); direction (1, 0.5, 0.5): level 12 = 111, every lower level 100.
  // o9 d12 at bits 54..49, then a 100 group every 6 bits from bit 45 down to bit 3.
  EXPECT_EQ(aila_code(c, {1, 0, 0}, kUnitBox), 0xE00E208208208208ull);
  // L = 0.25 x 1: b = (0.25, 0, 0), bx = 2^11: level 11's bx, bit 54.
  EXPECT_EQ(twopoint_code({0, 0, 0}, {1, 0, 0}, kInf, kUnitBox, 0.25f), 0x0040000000000000ull);
  // tmax = 0.1 < L: bx = floor(0.1f x 8192) = 819 = levels 9, 8, 5, 4, 1, 0 -> bits 42, 36, 18, 12 (1, 0 cut).
  EXPECT_EQ(twopoint_code({0, 0, 0}, {1, 0, 0}, 0.1f, kUnitBox, 0.25f), 0x0000041000041000ull);
  EXPECT_EQ(twopoint_code({0, 0, 0}, {1, 0, 0}, 0.f, kUnitBox, 0.25f), 0ull);  // tmax = 0: b = a
  // Box [0,8]^3, o = (7,0,0): L = min(2, inf, exit 1) = 1, b on the max face (8191); ax = 7168 = levels 12..10.
  const Bounds box8 = box_of({0, 0, 0}, {8, 8, 8});
  EXPECT_EQ(twopoint_code({7, 0, 0}, {1, 0, 0}, kInf, box8, 0.25f), 0x9249041041041041ull);
}

// The same hand-worked codes through make_encoder: a 32-bit key is the code's top half.
TEST(Keys, HandComputedKeysThroughTheEncoders) {
  const Bvh bvh = tiny_bvh();
  const EncoderContext ctx{kUnitBox, &bvh};
  const RayBatch centre = make_batch({ray({0.5f, 0.5f, 0.5f}, {1, 0, 0})});
  const RayBatch corner = make_batch({ray({0, 0, 0}, {1, 0, 0})});
  const RayBatch quarter = make_batch({ray({0.75f, 0.25f, 0}, {1, 0, 0})});
  const RayBatch leaf2 = make_batch({ray({0.6f, 0.5f, 0.5f}, {1, 0, 0})});
  struct Case {
    const char* name;
    const RayBatch& batch;
    uint64_t code;
  };
  for (const Case& c : std::vector<Case>{{"origin", quarter, 0x9800000000000000ull},
                                         {"reis", centre, 0xE000030000000000ull},
                                         {"costa", centre, 0xC0E0000000000000ull},
                                         {"aila", centre, 0xE00E208208208208ull},
                                         {"twopoint", corner, 0x0040000000000000ull},
                                         {"mlhcc", leaf2, 0xB000000000000000ull}}) {
    EXPECT_EQ(keys_of(std::string(c.name) + ":bits=64", ctx, c.batch)[0], c.code) << c.name;
    EXPECT_EQ(keys_of(std::string(c.name) + ":bits=32", ctx, c.batch)[0], c.code >> 32) << c.name;
  }
}

}  // namespace
}  // namespace raycoh
