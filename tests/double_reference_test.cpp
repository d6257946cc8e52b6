// The double-precision reference of `raycoh stability` (tracers/double_reference.h) on hand-built cases with
// known hits: interior hits with exact t, rays exactly through a shared edge and a shared vertex (watertight:
// never lost), misses, parallel rays, the [tmin, tmax] interval, the nearer of stacked planes, and a quad far
// from the origin; then the BVH walk against the brute force on the built-in scenes.
#include "tracers/double_reference.h"

#include <gtest/gtest.h>

#include <random>

#include "bvh/bvh_build.h"
#include "scenes/scene.h"

namespace raycoh {
namespace {

// A scene of the given triangles (one material), finalised like every loaded scene.
Scene triangles_scene(const std::vector<Vec3>& positions) {
  Scene s;
  s.name = "test";
  s.positions = positions;
  for (uint32_t i = 0; i < positions.size(); ++i) s.indices.push_back(i);
  s.tri_material.assign(positions.size() / 3, 0);
  s.materials.resize(1);
  finalize_scene(s);
  return s;
}

// The unit square at height z split along its diagonal (0,0)-(1,1), offset by (dx, dy): triangles 2i, 2i+1.
void push_quad(std::vector<Vec3>& p, float z, float dx = 0.f, float dy = 0.f) {
  const Vec3 a{dx, dy, z}, b{dx + 1.f, dy, z}, c{dx + 1.f, dy + 1.f, z}, d{dx, dy + 1.f, z};
  p.insert(p.end(), {a, b, c, a, c, d});
}

Ray down(float x, float y, float z = 5.f) { return Ray{{x, y, z}, 0.f, {0.f, 0.f, -1.f}, __builtin_huge_valf()}; }

TEST(DoubleReference, InteriorHitHasExactT) {
  std::vector<Vec3> p;
  push_quad(p, 1.f);
  const Scene s = triangles_scene(p);
  const RefHit h = brute_force_closest_hit(s, down(0.75f, 0.25f));
  ASSERT_TRUE(h.valid());
  EXPECT_EQ(h.prim, 0u);
  EXPECT_EQ(h.t, 4.0);
  EXPECT_EQ(brute_force_closest_hit(s, down(0.25f, 0.75f)).prim, 1u);
  // A tilted ray: from (0, 0, 3) towards (0.5, 0.25, 1), t = 1 with an unnormalised direction.
  const Ray tilted{{0.f, 0.f, 3.f}, 0.f, {0.5f, 0.25f, -2.f}, __builtin_huge_valf()};
  EXPECT_EQ(brute_force_closest_hit(s, tilted).t, 1.0);
}

TEST(DoubleReference, SharedEdgeAndVertexAreNeverLost) {
  std::vector<Vec3> p;
  push_quad(p, 0.f);
  const Scene s = triangles_scene(p);
  // Exactly on the diagonal both triangles are hit at the same t; the lower id wins the tie.
  for (float x : {0.125f, 0.5f, 0.8125f}) {
    const RefHit h = brute_force_closest_hit(s, down(x, x));
    ASSERT_TRUE(h.valid()) << x;
    EXPECT_EQ(h.prim, 0u);
    EXPECT_EQ(h.t, 5.0);
  }
  // Exactly through a shared vertex and along the outer edges: hits; just outside: misses.
  EXPECT_TRUE(brute_force_closest_hit(s, down(0.f, 0.f)).valid());
  EXPECT_TRUE(brute_force_closest_hit(s, down(1.f, 1.f)).valid());
  EXPECT_TRUE(brute_force_closest_hit(s, down(0.5f, 0.f)).valid());
  EXPECT_FALSE(brute_force_closest_hit(s, down(0.5f, -1e-7f)).valid());
  EXPECT_FALSE(brute_force_closest_hit(s, down(1.0000001f, 0.5f)).valid());
  // Oblique rays through the diagonal with awkward coordinates: the two edge functions are exact negatives,
  // so each such ray hits one of the two triangles.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uni(0.f, 1.f);
  for (int i = 0; i < 2000; ++i) {
    const float x = uni(rng);
    const Vec3 o{uni(rng) * 4.f - 2.f, uni(rng) * 4.f - 2.f, 3.f};
    const Ray r{o, 0.f, Vec3{x, x, 0.f} - o, __builtin_huge_valf()};
    EXPECT_TRUE(brute_force_closest_hit(s, r).valid()) << i;
  }
}

TEST(DoubleReference, MissesParallelRaysAndInterval) {
  std::vector<Vec3> p;
  push_quad(p, 0.f);
  const Scene s = triangles_scene(p);
  EXPECT_FALSE(brute_force_closest_hit(s, down(2.f, 0.5f)).valid());
  // In the plane, parallel to it: no hit.
  EXPECT_FALSE(brute_force_closest_hit(s, Ray{{-1.f, 0.5f, 0.f}, 0.f, {1.f, 0.f, 0.f}, 10.f}).valid());
  // Away from the plane.
  EXPECT_FALSE(brute_force_closest_hit(s, Ray{{0.5f, 0.25f, 1.f}, 0.f, {0.f, 0.f, 1.f}, 10.f}).valid());
  // The hit at t = 5 lies outside (0, 4] and outside [6, inf).
  Ray r = down(0.75f, 0.25f);
  r.tmax = 4.f;
  EXPECT_FALSE(brute_force_closest_hit(s, r).valid());
  r.tmax = __builtin_huge_valf();
  r.tmin = 6.f;
  EXPECT_FALSE(brute_force_closest_hit(s, r).valid());
  // Double-sided: from below.
  const RefHit below = brute_force_closest_hit(s, Ray{{0.75f, 0.25f, -2.f}, 0.f, {0.f, 0.f, 1.f}, 1e30f});
  EXPECT_EQ(below.prim, 0u);
  EXPECT_EQ(below.t, 2.0);
}

TEST(DoubleReference, NearerOfStackedPlanesAndFarFromOrigin) {
  std::vector<Vec3> p;
  push_quad(p, 0.f);
  push_quad(p, 1e-6f);  // 1e-6 above: the reference still tells them apart
  push_quad(p, 3.f);
  const Scene s = triangles_scene(p);
  EXPECT_EQ(brute_force_closest_hit(s, down(0.75f, 0.25f)).prim, 4u);
  EXPECT_EQ(brute_force_closest_hit(s, down(0.75f, 0.25f, 2.f)).prim, 2u);
  EXPECT_EQ(brute_force_closest_hit(s, Ray{{0.75f, 0.25f, -1.f}, 0.f, {0.f, 0.f, 1.f}, 1e30f}).prim, 0u);

  // A quad 1e7 from the origin (floats 1 apart there; tested on the raw triangles, since a loaded scene there is
  // rebased): a ray through its diagonal hits both halves at the exact t, and one just beside it one half.
  const float big = 1e7f;
  const Vec3 a{big, big, 0.f}, b{big + 8.f, big, 0.f}, c{big + 8.f, big + 8.f, 0.f}, d{big, big + 8.f, 0.f};
  const Ray diagonal = down(big + 3.f, big + 3.f, 7.f);
  EXPECT_EQ(reference_triangle_t(a, b, c, diagonal), 7.0);
  EXPECT_EQ(reference_triangle_t(a, c, d, diagonal), 7.0);
  const Ray beside = down(big + 4.f, big + 3.f, 7.f);
  EXPECT_EQ(reference_triangle_t(a, b, c, beside), 7.0);
  EXPECT_EQ(reference_triangle_t(a, c, d, beside), __builtin_huge_val());
}

TEST(DoubleReference, TriangleTestRejectsDegenerateTriangles) {
  const Ray r = down(0.f, 0.f);
  EXPECT_EQ(reference_triangle_t({0, 0, 0}, {0, 0, 0}, {0, 0, 0}, r), __builtin_huge_val());
  EXPECT_EQ(reference_triangle_t({-1, 0, 0}, {0, 0, 0}, {1, 0, 0}, r), __builtin_huge_val());  // collinear
}

// The BVH walk finds the brute force's answer (same t; the same triangle unless two are hit at that t).
void expect_bvh_matches_brute_force(const std::string& spec, int rays) {
  const Scene s = load_scene(spec);
  const Bvh bvh = build_bvh(s);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> uni(0.f, 1.f);
  const Vec3 lo = s.bounds.lo, ext = s.bounds.extent();
  int hits = 0;
  for (int i = 0; i < rays; ++i) {
    const Vec3 o = lo + Vec3{uni(rng) * ext.x, uni(rng) * ext.y, uni(rng) * ext.z};
    const Vec3 target = lo + Vec3{uni(rng) * ext.x, uni(rng) * ext.y, uni(rng) * ext.z};
    const Ray r{o, 0.f, target - o, __builtin_huge_valf()};
    const RefHit a = brute_force_closest_hit(s, r), b = reference_closest_hit(bvh, r);
    ASSERT_EQ(a.valid(), b.valid()) << spec << " ray " << i;
    if (!a.valid()) continue;
    ++hits;
    EXPECT_EQ(a.t, b.t) << spec << " ray " << i;
  }
  EXPECT_GT(hits, rays / 2) << spec;
}

TEST(DoubleReference, BvhWalkMatchesBruteForce) {
  expect_bvh_matches_brute_force("cornell", 2000);
  expect_bvh_matches_brute_force("voxels:size=8", 500);
}

}  // namespace
}  // namespace raycoh
