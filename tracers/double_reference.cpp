#include "tracers/double_reference.h"

#include <cmath>

#include "core/error.h"

namespace raycoh {

namespace {

struct D3 {
  double x, y, z;
};

D3 to_d(Vec3 v) { return {v.x, v.y, v.z}; }
D3 sub(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 cross_d(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dot_d(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

bool less_point(Vec3 a, Vec3 b) {
  if (a.x != b.x) return a.x < b.x;
  if (a.y != b.y) return a.y < b.y;
  return a.z < b.z;
}

// det(p - o, q - o, d), the same value (negated) whichever way round the edge is given.
double edge_function(Vec3 p, Vec3 q, D3 o, D3 d) {
  const bool swap = less_point(q, p);
  const D3 a = sub(to_d(swap ? q : p), o), b = sub(to_d(swap ? p : q), o);
  const double v = dot_d(cross_d(a, b), d);
  return swap ? -v : v;
}

// Entry distance of the ray into the box widened by a relative 1e-9, or +inf when it misses [tmin, tmax].
double box_entry(Vec3 lo, Vec3 hi, D3 o, D3 d, double tmin, double tmax) {
  const double lo_[3] = {lo.x, lo.y, lo.z}, hi_[3] = {hi.x, hi.y, hi.z};
  const double org[3] = {o.x, o.y, o.z}, dir[3] = {d.x, d.y, d.z};
  double t0 = tmin, t1 = tmax;
  for (int k = 0; k < 3; ++k) {
    const double pad = 1e-9 * (std::fabs(lo_[k]) + std::fabs(hi_[k])) + 1e-300;
    const double a = lo_[k] - pad, b = hi_[k] + pad;
    if (dir[k] == 0.0) {
      if (org[k] < a || org[k] > b) return __builtin_huge_val();
      continue;
    }
    double ta = (a - org[k]) / dir[k], tb = (b - org[k]) / dir[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::fmax(t0, ta * (1.0 - 1e-12));
    t1 = std::fmin(t1, tb * (1.0 + 1e-12));
  }
  return t0 <= t1 ? t0 : __builtin_huge_val();
}

void consider(double t, uint32_t prim, RefHit& best) {
  if (t < best.t || (t == best.t && prim < best.prim)) {
    best.t = t;
    best.prim = prim;
  }
}

}  // namespace

double reference_triangle_t(Vec3 v0, Vec3 v1, Vec3 v2, const Ray& ray, double* b1, double* b2) {
  const double inf = __builtin_huge_val();
  const D3 o = to_d(ray.org), d = to_d(ray.dir);
  const double u = edge_function(v1, v2, o, d), v = edge_function(v2, v0, o, d), w = edge_function(v0, v1, o, d);
  if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return inf;
  const D3 p0 = to_d(v0);
  const D3 ng = cross_d(sub(to_d(v1), p0), sub(to_d(v2), p0));
  const double denom = dot_d(ng, d);
  if (denom == 0.0 || u + v + w == 0.0) return inf;  // parallel to the plane, or a degenerate triangle
  const double t = dot_d(ng, sub(p0, o)) / denom;
  if (b1) *b1 = v / (u + v + w);
  if (b2) *b2 = w / (u + v + w);
  return t > ray.tmin && t < ray.tmax && std::isfinite(t) ? t : inf;
}

RefHit brute_force_closest_hit(const Scene& scene, const Ray& ray) {
  RefHit best;
  for (size_t i = 0; i < scene.triangle_count(); ++i) {
    const uint32_t* idx = &scene.indices[3 * i];
    const double t =
        reference_triangle_t(scene.positions[idx[0]], scene.positions[idx[1]], scene.positions[idx[2]], ray);
    if (t != __builtin_huge_val()) consider(t, static_cast<uint32_t>(i), best);
  }
  return best;
}

RefHit reference_closest_hit(const Bvh& bvh, const Ray& ray, const AlphaMaskView* alpha) {
  RefHit best;
  if (bvh.nodes.empty()) return best;
  const D3 o = to_d(ray.org), d = to_d(ray.dir);
  const double inf = __builtin_huge_val();
  int32_t stack[2 * kTraversalStackSize + 64];  // depth-first, both children pushed: depth x 1 + 1 entries
  int sp = 0;
  stack[sp++] = 0;
  while (sp > 0) {
    const int32_t ref = stack[--sp];
    if (is_leaf_ref(ref)) {
      const uint32_t first = leaf_first(ref), count = leaf_count(ref);
      for (uint32_t i = first; i < first + count; ++i) {
        const BvhTriangle& tri = bvh.tris[i];
        double b1 = 0, b2 = 0;
        const double t = reference_triangle_t(tri.v0, tri.v1, tri.v2, ray, &b1, &b2);
        if (t == inf) continue;
        if (alpha && !alpha_opaque(*alpha, tri.prim, static_cast<float>(b1), static_cast<float>(b2))) continue;
        consider(t, tri.prim, best);
      }
      continue;
    }
    const BvhNode& n = bvh.nodes[static_cast<size_t>(ref)];
    // Boxes are cut at the best t so far, widened, so that every triangle hit at that t is still tested.
    const double tmax = std::fmin(static_cast<double>(ray.tmax), best.t * (1.0 + 1e-9));
    for (int c = 0; c < 2; ++c) {
      const double e = box_entry(c == 0 ? n.lo0 : n.lo1, c == 0 ? n.hi0 : n.hi1, o, d, ray.tmin, tmax);
      if (e == inf) continue;
      RAYCOH_CHECK(sp < static_cast<int>(sizeof(stack) / sizeof(stack[0])), "reference traversal stack overflow");
      stack[sp++] = n.child[c];
    }
  }
  return best;
}

}  // namespace raycoh
