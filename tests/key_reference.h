// The slow bit-by-bit reference of the ray-reordering keys, written from the recipes in docs/design.md section 3
// independently of encoders/keys.h: RefBits appends fields one bit at a time, and ref_origin, ref_reis,
// ref_costa, ref_aila and ref_twopoint build each 64-bit code from quantised coordinates. Shared by keys_test,
// encoder_registry_test and mlhcc_test.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/vec.h"

namespace raycoh::test {

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

inline uint32_t bit(uint32_t v, int i) { return (v >> i) & 1u; }

// q = min(floor(u 2^b), 2^b - 1), u = clamp((p - lo) / (hi - lo), 0, 1) in float as the recipe states, the
// floor taken in double.
inline uint32_t ref_quantize(float p, float lo, float hi, int b) {
  const float extent = hi - lo;
  if (extent == 0.f) return 0;
  const double u = std::clamp(static_cast<double>((p - lo) / extent), 0.0, 1.0);
  return static_cast<uint32_t>(std::min(std::floor(u * std::ldexp(1.0, b)), std::ldexp(1.0, b) - 1.0));
}

struct RefQ {
  uint32_t v[3];
};
inline RefQ ref_point(Vec3 p, const Bounds& box, int b) {
  return {{ref_quantize(p.x, box.lo.x, box.hi.x, b), ref_quantize(p.y, box.lo.y, box.hi.y, b),
           ref_quantize(p.z, box.lo.z, box.hi.z, b)}};
}
inline RefQ ref_direction(Vec3 d, int b) {
  return {{ref_quantize(d.x, -1.f, 1.f, b), ref_quantize(d.y, -1.f, 1.f, b), ref_quantize(d.z, -1.f, 1.f, b)}};
}
// The recipe's float formulas; the CPU's atan2f/acosf values are the ones pinned.
inline uint32_t ref_phi(Vec3 d, int b) {
  const float phi = std::atan2(d.y, d.x) / (2.f * 3.14159265358979323846f) + 0.5f;
  return ref_quantize(phi, 0.f, 1.f, b);
}
inline uint32_t ref_theta(Vec3 d, int b) {
  const float theta = std::acos(std::clamp(d.z, -1.f, 1.f)) / 3.14159265358979323846f;
  return ref_quantize(theta, 0.f, 1.f, b);
}
// Level `level` of a point, x y z.
inline void push_level(RefBits& r, const RefQ& q, int level) {
  for (int a = 0; a < 3; ++a) r.push(bit(q.v[a], level), 1);
}

inline uint64_t ref_origin(Vec3 o, const Bounds& box) {
  const RefQ q = ref_point(o, box, 21);
  RefBits r;
  for (int l = 20; l >= 0; --l) push_level(r, q, l);
  return r.code();
}

inline uint64_t ref_reis(Vec3 o, Vec3 d, const Bounds& box) {
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

inline uint64_t ref_costa(Vec3 o, Vec3 d, const Bounds& box) {
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

inline uint64_t ref_aila(Vec3 o, Vec3 d, const Bounds& box) {
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

inline Vec3 ref_end_point(Vec3 o, Vec3 d, float tmax, const Bounds& box, float factor) {
  const Vec3 e = box.hi - box.lo;
  float length = std::min(factor * std::max({e.x, e.y, e.z}), tmax);
  for (int a = 0; a < 3; ++a) {
    if (d[a] > 0.f) length = std::min(length, (box.hi[a] - o[a]) / d[a]);
    if (d[a] < 0.f) length = std::min(length, (box.lo[a] - o[a]) / d[a]);
  }
  length = std::max(length, 0.f);
  return {o.x + d.x * length, o.y + d.y * length, o.z + d.z * length};
}

inline uint64_t ref_twopoint(Vec3 o, Vec3 d, float tmax, const Bounds& box, float factor) {
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

}  // namespace raycoh::test
