// Ray-reordering encoders: keys bit for bit against a slow bit-by-bit reference written from the recipes in
// DESIGN.md section 3 (and against literal codes worked out by hand for simple rays), for 32- and 64-bit keys;
// edge cases (max face, zero extent, axis directions, tmax = inf / 0, NaN / Inf, empty and one-ray batches);
// MLHCC cuts on a hand-built BVH and against a recursive reference on a real BVH; reorder() end to end.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <random>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "encoders/encoder.h"
#include "encoders/keys.h"
#include "encoders/mlhcc_cuts.h"
#include "encoders/reorder.h"

namespace raycoh {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// ---- the slow reference -------------------------------------------------------------------------------------

// Appends fields one bit at a time, most significant first; code() is the first 64 bits, zero-padded.
class RefBits {
 public:
  void push(uint64_t value, int width) {
    for (int i = width - 1; i >= 0; --i) bits_.push_back(static_cast<int>((value >> i) & 1u));
  }
  uint64_t code() const {
    uint64_t c = 0;
    for (size_t i = 0; i < 64; ++i) c = (c << 1) | (i < bits_.size() ? static_cast<uint64_t>(bits_[i]) : 0u);
    return c;
  }
  size_t size() const { return bits_.size(); }

 private:
  std::vector<int> bits_;
};

uint32_t bit(uint32_t v, int i) { return (v >> i) & 1u; }

// q = min(floor(u 2^b), 2^b - 1), u = clamp((p - lo) / (hi - lo), 0, 1) in float as the recipe states, the
// floor taken in double.
uint32_t ref_quantize(float p, float lo, float hi, int b) {
  const float extent = hi - lo;
  if (extent == 0.f) return 0;
  const double u = std::clamp(static_cast<double>((p - lo) / extent), 0.0, 1.0);
  return static_cast<uint32_t>(std::min(std::floor(u * std::ldexp(1.0, b)), std::ldexp(1.0, b) - 1.0));
}

struct RefQ {
  uint32_t v[3];
};
RefQ ref_point(Vec3 p, const Bounds& box, int b) {
  return {{ref_quantize(p.x, box.lo.x, box.hi.x, b), ref_quantize(p.y, box.lo.y, box.hi.y, b),
           ref_quantize(p.z, box.lo.z, box.hi.z, b)}};
}
RefQ ref_direction(Vec3 d, int b) {
  return {{ref_quantize(d.x, -1.f, 1.f, b), ref_quantize(d.y, -1.f, 1.f, b), ref_quantize(d.z, -1.f, 1.f, b)}};
}
// The recipe's float formulas; the CPU's atan2f/acosf values are the ones pinned.
uint32_t ref_phi(Vec3 d, int b) {
  const float phi = std::atan2(d.y, d.x) / (2.f * 3.14159265358979323846f) + 0.5f;
  return ref_quantize(phi, 0.f, 1.f, b);
}
uint32_t ref_theta(Vec3 d, int b) {
  const float theta = std::acos(std::clamp(d.z, -1.f, 1.f)) / 3.14159265358979323846f;
  return ref_quantize(theta, 0.f, 1.f, b);
}
// Level `level` of a point, x y z.
void push_level(RefBits& r, const RefQ& q, int level) {
  for (int a = 0; a < 3; ++a) r.push(bit(q.v[a], level), 1);
}

uint64_t ref_origin(Vec3 o, const Bounds& box) {
  const RefQ q = ref_point(o, box, 21);
  RefBits r;
  for (int l = 20; l >= 0; --l) push_level(r, q, l);
  return r.code();
}

uint64_t ref_reis(Vec3 o, Vec3 d, const Bounds& box) {
  const RefQ q = ref_point(o, box, 21);
  RefBits origin;
  for (int l = 20; l >= 0; --l) push_level(origin, q, l);
  RefBits r;
  r.push(origin.code() >> 42, 22);  // the top 22 bits of the origin code
  const uint32_t phi = ref_phi(d, 21), theta = ref_theta(d, 21);
  for (int l = 20; l >= 0; --l) {
    r.push(bit(phi, l), 1);
    r.push(bit(theta, l), 1);
  }
  EXPECT_EQ(r.size(), 64u);
  return r.code();
}

uint64_t ref_costa(Vec3 o, Vec3 d, const Bounds& box) {
  RefBits r;
  const uint32_t phi = ref_phi(d, 4), theta = ref_theta(d, 4);
  for (int l = 3; l >= 0; --l) {
    r.push(bit(phi, l), 1);
    r.push(bit(theta, l), 1);
  }
  const RefQ q = ref_point(o, box, 15);
  for (int l = 14; l >= 0; --l) push_level(r, q, l);
  EXPECT_EQ(r.size(), 53u);  // 11 low zero bits follow
  return r.code();
}

uint64_t ref_aila(Vec3 o, Vec3 d, const Bounds& box) {
  const RefQ qo = ref_point(o, box, 13);
  const RefQ qd = ref_direction(d, 13);
  RefBits r;
  for (int l : {12, 11, 10}) push_level(r, qo, l);
  for (int k = 0; k < 10; ++k) {
    push_level(r, qo, 9 - k);
    push_level(r, qd, 12 - k);
  }
  for (int l : {2, 1, 0}) push_level(r, qd, l);
  EXPECT_EQ(r.size(), 78u);
  return r.code();
}

Vec3 ref_end_point(Vec3 o, Vec3 d, float tmax, const Bounds& box, float factor) {
  const Vec3 e = box.hi - box.lo;
  float length = std::min(factor * std::max({e.x, e.y, e.z}), tmax);
  for (int a = 0; a < 3; ++a) {
    if (d[a] > 0.f) length = std::min(length, (box.hi[a] - o[a]) / d[a]);
    if (d[a] < 0.f) length = std::min(length, (box.lo[a] - o[a]) / d[a]);
  }
  length = std::max(length, 0.f);
  return {o.x + d.x * length, o.y + d.y * length, o.z + d.z * length};
}

uint64_t ref_twopoint(Vec3 o, Vec3 d, float tmax, const Bounds& box, float factor) {
  const RefQ a = ref_point(o, box, 13);
  const RefQ b = ref_point(ref_end_point(o, d, tmax, box, factor), box, 13);
  RefBits r;
  for (int l = 12; l >= 0; --l) {
    push_level(r, a, l);
    push_level(r, b, l);
  }
  EXPECT_EQ(r.size(), 78u);
  return r.code();
}

// ---- helpers ------------------------------------------------------------------------------------------------

RayBatch make_batch(const std::vector<Ray>& rays) {
  RayBatch b;
  b.width = static_cast<int>(rays.size());
  b.height = 1;
  b.resize(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    b.rays[i] = rays[i];
    b.pixel[i] = static_cast<uint32_t>(i);
    b.pdf[i] = static_cast<float>(i) + 0.5f;
  }
  return b;
}

Ray ray(Vec3 o, Vec3 d, float tmax = kInf) { return Ray{o, 0.f, d, tmax}; }

Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<float> n(0.f, 1.f);
  for (;;) {
    const Vec3 v{n(rng), n(rng), n(rng)};
    if (dot(v, v) > 1e-6f) return normalize(v);
  }
}

std::vector<Ray> random_rays(const Bounds& box, size_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  std::vector<Ray> rays;
  for (size_t i = 0; i < count; ++i) {
    const Vec3 o{box.lo.x + u(rng) * (box.hi.x - box.lo.x), box.lo.y + u(rng) * (box.hi.y - box.lo.y),
                 box.lo.z + u(rng) * (box.hi.z - box.lo.z)};
    const float tmax = i % 3 == 0 ? kInf : u(rng) * 2.f;
    rays.push_back(ray(o, random_unit(rng), tmax));
  }
  return rays;
}

std::vector<uint64_t> keys_of(const std::string& spec, const EncoderContext& ctx, const RayBatch& batch) {
  auto encoder = make_encoder(parse_plugin_spec(spec), ctx);
  std::vector<uint64_t> keys(batch.size(), 0xDEADBEEFull);
  encoder->encode(batch, keys.data());
  return keys;
}

Bounds box_of(Vec3 lo, Vec3 hi) { return Bounds{lo, hi}; }
Bvh tiny_bvh();
const Bounds kUnitBox = box_of({0.f, 0.f, 0.f}, {1.f, 1.f, 1.f});

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

// ---- every encoder against the reference, through make_encoder, 32- and 64-bit keys ------------------------

TEST(Encoders, KeysMatchTheBitByBitReference) {
  const Bounds box = box_of({-1.f, 0.f, -2.f}, {2.f, 3.f, -1.f});
  std::vector<Ray> rays = random_rays(box, 5000, 42);
  // Chosen rays: the box's corners and faces, the axis directions, tmax = 0.
  for (Vec3 d : {Vec3{1, 0, 0}, Vec3{-1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, -1, 0}, Vec3{0, 0, 1}, Vec3{0, 0, -1}}) {
    rays.push_back(ray(box.lo, d));
    rays.push_back(ray(box.hi, d));
    rays.push_back(ray(box.center(), d, 0.f));
    rays.push_back(ray({box.hi.x, 1.f, -1.5f}, d, 0.3f));
  }
  const RayBatch batch = make_batch(rays);
  const EncoderContext ctx{box, nullptr};
  struct Case {
    std::string spec;
    std::function<uint64_t(const Ray&)> ref;
  };
  const std::vector<Case> cases = {
      {"origin", [&](const Ray& r) { return ref_origin(r.org, box); }},
      {"reis", [&](const Ray& r) { return ref_reis(r.org, r.dir, box); }},
      {"costa", [&](const Ray& r) { return ref_costa(r.org, r.dir, box); }},
      {"aila", [&](const Ray& r) { return ref_aila(r.org, r.dir, box); }},
      {"twopoint", [&](const Ray& r) { return ref_twopoint(r.org, r.dir, r.tmax, box, 0.25f); }},
      {"twopoint:L=0.6", [&](const Ray& r) { return ref_twopoint(r.org, r.dir, r.tmax, box, 0.6f); }},
  };
  for (const Case& c : cases) {
    const std::string sep = c.spec.find(':') == std::string::npos ? ":" : ",";
    const std::vector<uint64_t> k64 = keys_of(c.spec + sep + "bits=64", ctx, batch);
    const std::vector<uint64_t> k32 = keys_of(c.spec, ctx, batch);  // 32 is the default
    for (size_t i = 0; i < rays.size(); ++i) {
      const uint64_t expected = c.ref(rays[i]);
      ASSERT_EQ(k64[i], expected) << c.spec << " ray " << i;
      ASSERT_EQ(k32[i], expected >> 32) << c.spec << " ray " << i;
    }
  }
}

TEST(Encoders, ThirtyTwoBitKeysHoldTheDocumentedBitsPerComponent) {
  // Origin: x 11, y 11, z 10 bits. Moving z by one 10-bit step changes the 32-bit key; a 2^-11 step does not.
  const EncoderContext ctx{kUnitBox, nullptr};
  const RayBatch batch = make_batch({ray({0, 0, 0}, {1, 0, 0}), ray({0, 0, 1.f / 1024}, {1, 0, 0}),
                                     ray({0, 0, 1.f / 2048}, {1, 0, 0}), ray({1.f / 2048, 0, 0}, {1, 0, 0})});
  const auto k = keys_of("origin", ctx, batch);
  EXPECT_NE(k[1], k[0]);
  EXPECT_EQ(k[2], k[0]);
  EXPECT_NE(k[3], k[0]);  // x keeps 11 bits
}

TEST(Encoders, NonFiniteInputHasDefinedKeys) {
  const EncoderContext ctx{kUnitBox, nullptr};
  Bvh bvh;  // an empty BVH: mlhcc has no cuts and gives 0
  const EncoderContext ctx_bvh{kUnitBox, &bvh};
  const RayBatch batch = make_batch({
      ray({kNaN, kNaN, kNaN}, {1, 0, 0}),
      ray({kInf, kInf, kInf}, {1, 0, 0}),
      ray({-kInf, -kInf, -kInf}, {1, 0, 0}),
      ray({0.5f, 0.5f, 0.5f}, {kNaN, kNaN, kNaN}),
      ray({0.5f, 0.5f, 0.5f}, {kInf, -kInf, kInf}),
      ray({0.5f, 0.5f, 0.5f}, {0, 0, 0}),
      ray({0.5f, 0.5f, 0.5f}, {1, 0, 0}, kNaN),
      ray({0.5f, 0.5f, 0.5f}, {1, 0, 0}, -1.f),
  });
  for (const char* name : {"origin", "reis", "costa", "aila", "twopoint", "mlhcc"}) {
    const auto k = keys_of(std::string(name) + ":bits=64", name == std::string("mlhcc") ? ctx_bvh : ctx, batch);
    EXPECT_EQ(k.size(), batch.size());
    for (size_t i = 0; i < k.size(); ++i) EXPECT_NE(k[i], 0xDEADBEEFull) << name << " ray " << i;
  }
  const auto origin = keys_of("origin:bits=64", ctx, batch);
  EXPECT_EQ(origin[0], 0ull);                   // NaN -> 0
  EXPECT_EQ(origin[1], 0xFFFFFFFFFFFFFFFEull);  // +Inf -> 2^21 - 1
  EXPECT_EQ(origin[2], 0ull);                   // -Inf -> 0
  const auto reis = keys_of("reis:bits=64", ctx, batch);
  EXPECT_EQ(reis[3], 0xE000000000000000ull);  // NaN direction: phi = theta = 0
  const auto tp = keys_of("twopoint:bits=64", ctx, batch);
  // A NaN tmax is no limit; a negative one gives L = 0.
  EXPECT_EQ(tp[6], twopoint_code({0.5f, 0.5f, 0.5f}, {1, 0, 0}, kInf, kUnitBox, 0.25f));
  EXPECT_EQ(tp[7], twopoint_code({0.5f, 0.5f, 0.5f}, {1, 0, 0}, 0.f, kUnitBox, 0.25f));
  EXPECT_NE(tp[6], tp[7]);
  EXPECT_EQ(tp[0], 0ull);
  const auto ml = keys_of("mlhcc:bits=64", ctx_bvh, batch);
  for (uint64_t key : ml) EXPECT_EQ(key, 0ull);
}

// ---- MLHCC --------------------------------------------------------------------------------------------------

// Root over x in [0,1]: node 1 = [0,.5], node 2 = [.5,1], each with two leaves of width .25 (y, z in [0,1]).
// Surface areas (half): root 3, nodes 2, leaves 1.5.
Bvh tiny_bvh() {
  auto node = [](Vec3 lo0, Vec3 hi0, Vec3 lo1, Vec3 hi1, int32_t c0, int32_t c1) {
    BvhNode n{};
    n.lo0 = lo0;
    n.hi0 = hi0;
    n.lo1 = lo1;
    n.hi1 = hi1;
    n.child[0] = c0;
    n.child[1] = c1;
    return n;
  };
  Bvh bvh;
  bvh.nodes.push_back(node({0, 0, 0}, {0.5f, 1, 1}, {0.5f, 0, 0}, {1, 1, 1}, 1, 2));
  bvh.nodes.push_back(
      node({0, 0, 0}, {0.25f, 1, 1}, {0.25f, 0, 0}, {0.5f, 1, 1}, make_leaf_ref(0, 1), make_leaf_ref(1, 1)));
  bvh.nodes.push_back(
      node({0.5f, 0, 0}, {0.75f, 1, 1}, {0.75f, 0, 0}, {1, 1, 1}, make_leaf_ref(2, 1), make_leaf_ref(3, 1)));
  bvh.bounds = kUnitBox;
  return bvh;
}

TEST(Mlhcc, CutsOfAHandBuiltTree) {
  const Bvh bvh = tiny_bvh();
  // lambda = 0.125: no inner node is small enough, so the one level is the four leaves (2 bits).
  const MlhccCutTable fine = build_mlhcc_cuts(bvh, 0.125f, MlhccRanks::Compressed);
  EXPECT_EQ(fine.level_bits, (std::vector<uint32_t>{2}));
  EXPECT_EQ(fine.level_sizes, (std::vector<uint32_t>{4}));
  EXPECT_EQ(fine.cuts[1].rank[1], 1u);
  EXPECT_EQ(fine.cuts[2].rank[0], 2u);
  EXPECT_EQ(fine.summary(), "levels=1 bits=2 nodes=4");
  // lambda = 0.7: nodes 1 and 2 (2 <= 2.1) form level 1, the leaves level 2 (two per parent: 1 bit each) ...
  const MlhccCutTable coarse = build_mlhcc_cuts(bvh, 0.7f, MlhccRanks::Compressed);
  EXPECT_EQ(coarse.level_bits, (std::vector<uint32_t>{1, 1}));
  EXPECT_EQ(coarse.level_sizes, (std::vector<uint32_t>{2, 4}));
  // ... and numbered within the whole level, 2 bits.
  const MlhccCutTable global = build_mlhcc_cuts(bvh, 0.7f, MlhccRanks::Global);
  EXPECT_EQ(global.level_bits, (std::vector<uint32_t>{1, 2}));
  EXPECT_EQ(global.cuts[2].rank[1], 3u);
}

TEST(Mlhcc, HandComputedCodes) {
  const Bvh bvh = tiny_bvh();
  const EncoderContext ctx{kUnitBox, &bvh};
  // Origin in leaf 2; end point o + 0.25 x (1,0,0) = (0.85, .5, .5) in leaf 3.
  const RayBatch batch = make_batch({ray({0.6f, 0.5f, 0.5f}, {1, 0, 0}),
                                     ray({0.5f, 0.5f, 0.5f}, {0, 1, 0}),    // on the shared face: child 0
                                     ray({2.f, 0.5f, 0.5f}, {1, 0, 0}),     // outside: clamped into leaf 3
                                     ray({kNaN, 0.5f, 0.5f}, {1, 0, 0})});  // NaN: box's low face, leaf 0
  const auto fine = keys_of("mlhcc:bits=64", ctx, batch);
  EXPECT_EQ(fine[0], 0xB000000000000000ull);  // 10 11
  EXPECT_EQ(fine[1], 0x5000000000000000ull);  // 01 01 (y moves inside leaf 1)
  EXPECT_EQ(fine[2], 0xF000000000000000ull);  // 11 11
  // NaN x: origin at x = 0 (leaf 0); end point (NaN) likewise.
  EXPECT_EQ(fine[3], 0x0000000000000000ull);
  EXPECT_EQ(keys_of("mlhcc", ctx, batch)[0], 0xB0000000ull);
  EXPECT_EQ(keys_of("mlhcc:points=origin,bits=64", ctx, batch)[0], 0x8000000000000000ull);  // 10
  EXPECT_EQ(keys_of("mlhcc:lambda=0.7,bits=64", ctx, batch)[0], 0xD000000000000000ull);     // 1 1 | 0 1
  EXPECT_EQ(keys_of("mlhcc:lambda=0.7,ranks=global,bits=64", ctx, batch)[0],
            0xEC00000000000000ull);                                               // 1 1 | 10 11
  EXPECT_EQ(keys_of("mlhcc:L=0,bits=64", ctx, batch)[0], 0xA000000000000000ull);  // end = origin: 10 10
}

// A recursive reference of the cut rule, written independently of the stack-based builder.
struct RefMlhcc {
  const Bvh& bvh;
  float lambda;
  bool global;
  std::map<std::pair<uint32_t, int>, std::pair<uint32_t, uint32_t>> cut;  // (node, slot) -> (level, rank)
  std::vector<uint32_t> widths, sizes;

  static float area(Vec3 lo, Vec3 hi) { return Bounds{lo, hi}.half_area(); }
  float child_area(uint32_t node, int slot) const {
    const BvhNode& n = bvh.nodes[node];
    return slot == 0 ? area(n.lo0, n.hi0) : area(n.lo1, n.hi1);
  }
  static uint32_t bits_for(size_t n) {
    uint32_t w = 0;
    while ((size_t{1} << w) < n) ++w;
    return w;
  }
  // The cut nodes directly beneath a cut node (the children of `node` are its first candidates), DFS order.
  void cut_children(uint32_t node, float parent_area, std::vector<std::pair<uint32_t, int>>& out) const {
    for (int slot = 0; slot < 2; ++slot) {
      const int32_t ref = bvh.nodes[node].child[slot];
      if (is_leaf_ref(ref) || child_area(node, slot) <= lambda * parent_area)
        out.push_back({node, slot});
      else
        cut_children(static_cast<uint32_t>(ref), parent_area, out);
    }
  }
  void build(uint32_t node, float node_area, uint32_t level) {
    std::vector<std::pair<uint32_t, int>> children;
    cut_children(node, node_area, children);
    if (sizes.size() <= level) {
      sizes.resize(level + 1, 0);
      widths.resize(level + 1, 0);
    }
    for (const auto& c : children) cut[c] = {level + 1, global ? sizes[level]++ : 0};
    if (!global) {
      for (uint32_t i = 0; i < children.size(); ++i) cut[children[i]].second = i;
      sizes[level] += static_cast<uint32_t>(children.size());
      widths[level] = std::max(widths[level], bits_for(children.size()));
    }
    for (const auto& c : children) {
      const int32_t ref = bvh.nodes[c.first].child[c.second];
      if (!is_leaf_ref(ref)) build(static_cast<uint32_t>(ref), child_area(c.first, c.second), level + 1);
    }
  }
  RefMlhcc(const Bvh& b, float l, bool g) : bvh(b), lambda(l), global(g) {
    const BvhNode& root = bvh.nodes[0];
    Bounds box{root.lo0, root.hi0};
    box.grow(Bounds{root.lo1, root.hi1});
    build(0, box.half_area(), 0);
    if (global)
      for (size_t l = 0; l < sizes.size(); ++l) widths[l] = bits_for(sizes[l]);
  }
  // Rank per level (index level - 1) of the cut nodes on p's descent; missing levels are 0.
  std::vector<uint32_t> path_ranks(Vec3 p) const {
    std::vector<uint32_t> ranks(widths.size(), 0);
    uint32_t node = 0;
    for (;;) {
      const BvhNode& n = bvh.nodes[node];
      auto dist = [&](Vec3 lo, Vec3 hi) {
        float s = 0.f;
        for (int a = 0; a < 3; ++a) {
          const float d = std::max({lo[a] - p[a], p[a] - hi[a], 0.f});
          s = s + d * d;
        }
        return s;
      };
      const float d0 = dist(n.lo0, n.hi0), d1 = dist(n.lo1, n.hi1);
      const int slot = d0 < d1 ? 0 : d1 < d0 ? 1 : (area(n.lo1, n.hi1) < area(n.lo0, n.hi0) ? 1 : 0);
      auto it = cut.find({node, slot});
      if (it != cut.end()) ranks[it->second.first - 1] = it->second.second;
      if (is_leaf_ref(n.child[slot])) return ranks;
      node = static_cast<uint32_t>(n.child[slot]);
    }
  }
  uint64_t code(const Ray& r, const Bounds& box, float factor) const {
    auto clamp = [&](Vec3 p) {
      return Vec3{std::clamp(p.x, box.lo.x, box.hi.x), std::clamp(p.y, box.lo.y, box.hi.y),
                  std::clamp(p.z, box.lo.z, box.hi.z)};
    };
    const auto a = path_ranks(clamp(r.org));
    const auto b = path_ranks(clamp(ref_end_point(r.org, r.dir, r.tmax, box, factor)));
    RefBits bits;
    for (size_t l = 0; l < widths.size(); ++l) {
      bits.push(a[l], static_cast<int>(widths[l]));
      bits.push(b[l], static_cast<int>(widths[l]));
    }
    return bits.code();
  }
};

TEST(Mlhcc, MatchesTheRecursiveReferenceOnARealBvh) {
  const Scene scene = load_scene("voxels");
  const Bvh bvh = build_bvh(scene);
  const EncoderContext ctx{scene.bounds, &bvh};
  const RayBatch batch = make_batch(random_rays(scene.bounds, 4000, 5));
  for (const auto& [lambda, global] :
       std::vector<std::pair<float, bool>>{{0.125f, false}, {0.3f, false}, {0.125f, true}, {0.02f, false}}) {
    const RefMlhcc ref(bvh, lambda, global);
    const MlhccCutTable table = build_mlhcc_cuts(bvh, lambda, global ? MlhccRanks::Global : MlhccRanks::Compressed);
    ASSERT_EQ(table.level_bits, ref.widths) << lambda;
    ASSERT_EQ(table.level_sizes, ref.sizes) << lambda;
    const std::string spec = fmt::format("mlhcc:lambda={},ranks={}", lambda, global ? "global" : "compressed");
    const auto k64 = keys_of(spec + ",bits=64", ctx, batch);
    const auto k32 = keys_of(spec, ctx, batch);
    size_t distinct = 0;
    for (size_t i = 0; i < batch.size(); ++i) {
      const uint64_t expected = ref.code(batch.rays[i], scene.bounds, 0.25f);
      ASSERT_EQ(k64[i], expected) << spec << " ray " << i;
      ASSERT_EQ(k32[i], expected >> 32) << spec << " ray " << i;
      distinct += i > 0 && k64[i] != k64[i - 1];
    }
    EXPECT_GT(distinct, batch.size() / 2) << spec;  // the codes discriminate
  }
}

TEST(Mlhcc, NeedsTheBvh) {
  EXPECT_THROW(make_encoder(parse_plugin_spec("mlhcc"), EncoderContext{kUnitBox, nullptr}), Error);
}

// ---- registry, parameters, reorder() ------------------------------------------------------------------------

TEST(Encoders, RegistryAndParameters) {
  std::vector<std::string> names;
  for (const auto& info : encoder_infos()) names.push_back(info.name);
  EXPECT_EQ(names, (std::vector<std::string>{"none", "origin", "reis", "costa", "aila", "twopoint", "mlhcc"}));
  const Bvh bvh = tiny_bvh();
  const EncoderContext ctx{box_of({-1, 0, -1}, {1, 2, 1}), &bvh};
  EXPECT_EQ(make_encoder(parse_plugin_spec("origin"), ctx)->params(), "bits=32,box=-1/0/-1..1/2/1");
  EXPECT_EQ(make_encoder(parse_plugin_spec("reis:bits=64"), ctx)->key_bits(), 64);
  EXPECT_EQ(make_encoder(parse_plugin_spec("twopoint"), ctx)->params(), "bits=32,L=0.25,box=-1/0/-1..1/2/1");
  const auto mlhcc = make_encoder(parse_plugin_spec("mlhcc"), ctx);
  EXPECT_EQ(mlhcc->params(), "bits=32,lambda=0.125,L=0.25,points=both,ranks=compressed,box=-1/0/-1..1/2/1");
  EXPECT_EQ(mlhcc->details(), "levels=1 bits=2 nodes=4");
  EXPECT_EQ(mlhcc->name(), "mlhcc");
  const auto none = make_encoder(parse_plugin_spec("none"), ctx);
  EXPECT_EQ(none->key_bits(), 0);
  EXPECT_EQ(none->params(), "");
  EXPECT_THROW(make_encoder(parse_plugin_spec("morton"), ctx), Error);
  EXPECT_THROW(make_encoder(parse_plugin_spec("origin:bits=16"), ctx), Error);
  EXPECT_THROW(make_encoder(parse_plugin_spec("origin:lambda=0.5"), ctx), Error);
  EXPECT_THROW(make_encoder(parse_plugin_spec("none:bits=32"), ctx), Error);
  EXPECT_THROW(make_encoder(parse_plugin_spec("mlhcc:lambda=1"), ctx), Error);
  EXPECT_THROW(make_encoder(parse_plugin_spec("twopoint:L=-1"), ctx), Error);
  try {
    make_encoder(parse_plugin_spec("reis:bitz=64"), ctx);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("encoder 'reis'"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("bits"), std::string::npos);
  }
  EXPECT_EQ(parse_permute_mode("indirect"), PermuteMode::Indirect);
  EXPECT_THROW(parse_permute_mode("copy"), Error);
}

TEST(Reorder, SortsByKeyStablyAndPermutesEveryArray) {
  const Bounds box = box_of({0, 0, 0}, {4, 4, 4});
  // Few distinct keys (origins on a 2x2x2 grid), so stability is exercised.
  std::vector<Ray> rays;
  std::mt19937 rng(9);
  for (int i = 0; i < 3000; ++i)
    rays.push_back(ray({float(rng() % 2) * 2.f, float(rng() % 2) * 2.f, float(rng() % 2) * 2.f}, random_unit(rng)));
  const RayBatch in = make_batch(rays);
  for (const char* spec : {"origin", "reis:bits=64", "costa", "aila", "twopoint"}) {
    auto encoder = make_encoder(parse_plugin_spec(spec), EncoderContext{box, nullptr});
    std::vector<uint64_t> keys(in.size());
    encoder->encode(in, keys.data());
    for (PermuteMode mode : {PermuteMode::Physical, PermuteMode::Indirect}) {
      RayBatch out;
      std::vector<uint32_t> order;
      ReorderTimings t;
      ASSERT_TRUE(reorder(*encoder, in, mode, out, order, t));
      ASSERT_TRUE(is_index_permutation(order, in.size()));
      std::vector<uint32_t> expected(in.size());
      std::iota(expected.begin(), expected.end(), 0u);
      std::stable_sort(expected.begin(), expected.end(), [&](uint32_t a, uint32_t b) { return keys[a] < keys[b]; });
      ASSERT_EQ(order, expected) << spec;
      for (size_t i = 0; i < in.size(); ++i) ASSERT_EQ(encoder->workspace().keys[i], keys[order[i]]);
      EXPECT_GE(t.key_ms, 0.0);
      EXPECT_GE(t.sort_ms, 0.0);
      if (mode == PermuteMode::Indirect) {
        EXPECT_EQ(t.permute_ms, 0.0);
        EXPECT_EQ(out.size(), 0u);
        continue;
      }
      ASSERT_EQ(out.size(), in.size());
      EXPECT_EQ(out.width, in.width);
      for (size_t i = 0; i < in.size(); ++i) {
        const uint32_t j = order[i];
        ASSERT_EQ(out.rays[i].org.x, in.rays[j].org.x);
        ASSERT_EQ(out.rays[i].dir.z, in.rays[j].dir.z);
        ASSERT_EQ(out.pixel[i], in.pixel[j]);
        ASSERT_EQ(out.pdf[i], in.pdf[j]);
        ASSERT_EQ(out.material[i], in.material[j]);
      }
    }
  }
}

TEST(Reorder, NoneEmptyAndOneRayBatches) {
  const Bvh bvh = tiny_bvh();
  const EncoderContext ctx{kUnitBox, &bvh};
  RayBatch out;
  std::vector<uint32_t> order = {7, 7};
  ReorderTimings t{1, 2, 3};
  auto none = make_encoder(parse_plugin_spec("none"), ctx);
  EXPECT_FALSE(reorder(*none, make_batch({ray({0, 0, 0}, {1, 0, 0})}), PermuteMode::Physical, out, order, t));
  EXPECT_TRUE(order.empty());
  EXPECT_EQ(t.total_ms(), 0.0);
  for (const char* name : {"origin", "reis", "costa", "aila", "twopoint", "mlhcc"}) {
    auto encoder = make_encoder(parse_plugin_spec(name), ctx);
    for (size_t n : {0, 1}) {
      const RayBatch in = make_batch(n ? std::vector<Ray>{ray({0.3f, 0.2f, 0.1f}, {0, 0, 1})} : std::vector<Ray>{});
      ASSERT_TRUE(reorder(*encoder, in, PermuteMode::Physical, out, order, t)) << name;
      EXPECT_EQ(order.size(), n);
      EXPECT_EQ(out.size(), n);
      if (n) {
        EXPECT_EQ(order[0], 0u);
      }
    }
  }
}

TEST(Reorder, KeysAndOrderDoNotDependOnTheThreadCount) {
  const Scene scene = load_scene("cornell");
  const Bvh bvh = build_bvh(scene);
  const RayBatch in = make_batch(random_rays(scene.bounds, 200000, 13));
  for (const char* spec : {"aila", "mlhcc"}) {
    std::vector<std::vector<uint32_t>> orders;
    for (int threads : {1, 2, 7}) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      auto encoder = make_encoder(parse_plugin_spec(spec), EncoderContext{scene.bounds, &bvh});
      RayBatch out;
      std::vector<uint32_t> order;
      ReorderTimings t;
      reorder(*encoder, in, PermuteMode::Physical, out, order, t);
      orders.push_back(order);
    }
    EXPECT_EQ(orders[0], orders[1]) << spec;
    EXPECT_EQ(orders[0], orders[2]) << spec;
  }
}

}  // namespace
}  // namespace raycoh
