// A double-precision reference for closest hits, the yardstick of `raycoh stability` (harness/stability.cpp).
//
// Triangle test: the three edge functions are signed volumes det(p - o, q - o, d) of the ray (o, d) with each
// edge (p, q), evaluated in double with the edge's end points in one canonical order (the lexicographically
// smaller first, the sign flipped back), so two triangles sharing an edge get exactly opposite values for it and
// no ray slips between them (watertight). Double-sided; a value of exactly zero counts as inside (a ray through
// an edge or vertex hits every triangle there). t from the plane equation in double.
//
// Candidates: reference_closest_hit() walks the BVH in double with every box widened by a relative 1e-9 (no
// triangle is lost to a box test's rounding) and tests every triangle of every leaf it reaches, keeping the
// nearest; brute_force_closest_hit() tests every triangle of the scene (for the tests, and small scenes).
// Alpha MASK cut-outs: with `alpha`, a candidate on a transparent texel (core/alpha_mask.h, at the double
// barycentrics rounded to float) is skipped, as the tracers skip it.
#pragma once

#include <cstdint>

#include "bvh/bvh_build.h"
#include "core/ray.h"
#include "scenes/scene.h"

namespace raycoh {

struct RefHit {
  double t = __builtin_huge_val();
  uint32_t prim = kNoHit;
  bool valid() const { return prim != kNoHit; }
};

// t of the ray's hit on triangle (v0, v1, v2) in (tmin, tmax), or +inf when it misses (or is degenerate); b1 and
// b2, when given, get the barycentric weights of v1 and v2 of a hit.
double reference_triangle_t(Vec3 v0, Vec3 v1, Vec3 v2, const Ray& ray, double* b1 = nullptr, double* b2 = nullptr);

// Nearest hit over every triangle of the scene; ties at equal t go to the lower primitive id.
RefHit brute_force_closest_hit(const Scene& scene, const Ray& ray);

// The same answer through the BVH's candidates.
RefHit reference_closest_hit(const Bvh& bvh, const Ray& ray, const AlphaMaskView* alpha = nullptr);

}  // namespace raycoh
