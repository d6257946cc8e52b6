// Small 3-vector and bounding-box math shared by host and device code.
#pragma once

#include "core/platform.h"

#if !defined(__CUDACC__)
#include <cmath>
#endif

namespace raycoh {

struct Vec3 {
  float x = 0.f, y = 0.f, z = 0.f;
  constexpr Vec3() = default;
  RAYCOH_HD constexpr Vec3(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
  RAYCOH_HD constexpr explicit Vec3(float s) : x(s), y(s), z(s) {}
  RAYCOH_HD float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  RAYCOH_HD float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
};
static_assert(sizeof(Vec3) == 12, "Vec3 is three packed floats");

RAYCOH_HD RAYCOH_INLINE Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
RAYCOH_HD RAYCOH_INLINE Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
RAYCOH_HD RAYCOH_INLINE Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
RAYCOH_HD RAYCOH_INLINE Vec3 operator*(Vec3 a, Vec3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
RAYCOH_HD RAYCOH_INLINE Vec3 operator*(Vec3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
RAYCOH_HD RAYCOH_INLINE Vec3 operator*(float s, Vec3 a) { return {a.x * s, a.y * s, a.z * s}; }
RAYCOH_HD RAYCOH_INLINE Vec3 operator/(Vec3 a, float s) { return {a.x / s, a.y / s, a.z / s}; }
RAYCOH_HD RAYCOH_INLINE Vec3& operator+=(Vec3& a, Vec3 b) {
  a = a + b;
  return a;
}

// Plain compare-and-select min/max: one instruction on CPU and GPU (fminf/fmaxf are library calls on x86
// without -ffast-math). Their NaN handling differs from fminf, which is fine: traversal never sees NaN.
RAYCOH_HD RAYCOH_INLINE float min_f(float a, float b) { return a < b ? a : b; }
RAYCOH_HD RAYCOH_INLINE float max_f(float a, float b) { return a > b ? a : b; }

RAYCOH_HD RAYCOH_INLINE float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
RAYCOH_HD RAYCOH_INLINE Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
RAYCOH_HD RAYCOH_INLINE float length(Vec3 a) { return sqrtf(dot(a, a)); }
RAYCOH_HD RAYCOH_INLINE Vec3 normalize(Vec3 a) { return a * (1.f / sqrtf(dot(a, a))); }
RAYCOH_HD RAYCOH_INLINE Vec3 vmin(Vec3 a, Vec3 b) { return {fminf(a.x, b.x), fminf(a.y, b.y), fminf(a.z, b.z)}; }
RAYCOH_HD RAYCOH_INLINE Vec3 vmax(Vec3 a, Vec3 b) { return {fmaxf(a.x, b.x), fmaxf(a.y, b.y), fmaxf(a.z, b.z)}; }
RAYCOH_HD RAYCOH_INLINE float max_component(Vec3 a) { return fmaxf(a.x, fmaxf(a.y, a.z)); }
RAYCOH_HD RAYCOH_INLINE bool is_finite(float x) {
#if defined(__CUDA_ARCH__)
  return isfinite(x);
#else
  return std::isfinite(x);
#endif
}
RAYCOH_HD RAYCOH_INLINE bool is_finite(Vec3 a) { return is_finite(a.x) && is_finite(a.y) && is_finite(a.z); }

// Axis-aligned box; the default box is empty (lo = +inf, hi = -inf) so that grow() works from nothing.
struct Bounds {
  Vec3 lo{__builtin_huge_valf()};
  Vec3 hi{-__builtin_huge_valf()};
  RAYCOH_HD void grow(Vec3 p) {
    lo = vmin(lo, p);
    hi = vmax(hi, p);
  }
  RAYCOH_HD void grow(const Bounds& b) {
    lo = vmin(lo, b.lo);
    hi = vmax(hi, b.hi);
  }
  RAYCOH_HD bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
  RAYCOH_HD Vec3 extent() const { return hi - lo; }
  RAYCOH_HD Vec3 center() const { return (lo + hi) * 0.5f; }
  RAYCOH_HD bool contains(const Bounds& b) const {
    return lo.x <= b.lo.x && lo.y <= b.lo.y && lo.z <= b.lo.z && hi.x >= b.hi.x && hi.y >= b.hi.y && hi.z >= b.hi.z;
  }
  RAYCOH_HD float half_area() const {
    if (empty()) return 0.f;
    Vec3 e = extent();
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
};

}  // namespace raycoh
