// Sampling and traversal math: frames, cosine and GGX sampling against their pdfs (goodness of fit with fixed
// seeds), offsets, the watertight triangle test on hand-made cases, and RNG properties.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/bsdf.h"
#include "core/rng.h"
#include "core/traverse.h"

namespace raycoh {
namespace {

// Pearson chi-square statistic of counts against equal expected frequencies.
double chi_square_uniform(const std::vector<int>& counts, int total) {
  const double expected = static_cast<double>(total) / counts.size();
  double chi2 = 0;
  for (int c : counts) chi2 += (c - expected) * (c - expected) / expected;
  return chi2;
}

TEST(Frame, OrthonormalForAllNormalsIncludingPoles) {
  const std::vector<Vec3> normals = {{0, 0, 1},
                                     {0, 0, -1},
                                     {1, 0, 0},
                                     {0, 1, 0},
                                     {0, 0, -0.9999999f},
                                     normalize(Vec3{1e-7f, 0, -1}),
                                     normalize(Vec3{0.3f, -0.4f, 0.5f})};
  for (Vec3 n : normals) {
    const Frame f = make_frame(n);
    EXPECT_NEAR(dot(f.t, f.t), 1.f, 1e-5f);
    EXPECT_NEAR(dot(f.b, f.b), 1.f, 1e-5f);
    EXPECT_NEAR(dot(f.t, f.b), 0.f, 1e-5f);
    EXPECT_NEAR(dot(f.t, f.n), 0.f, 1e-5f);
    EXPECT_NEAR(dot(f.b, f.n), 0.f, 1e-5f);
    EXPECT_TRUE(is_finite(f.t) && is_finite(f.b));
  }
}

// Under the cosine distribution, cos^2(theta) and phi / 2pi are independent and uniform on [0, 1).
TEST(Sampling, CosineHemisphereFitsItsDistribution) {
  const int n = 200000, bins = 16;
  std::vector<int> c2(bins, 0), phi(bins, 0);
  for (int i = 0; i < n; ++i) {
    const Vec3 d = sample_cosine_hemisphere(rng_float(7, 0, i, 0), rng_float(7, 0, i, 1));
    ASSERT_GE(d.z, 0.f);
    ASSERT_NEAR(length(d), 1.f, 1e-5f);
    c2[std::min(bins - 1, static_cast<int>(d.z * d.z * bins))]++;
    const float p = (std::atan2(d.y, d.x) + kPi) / (2 * kPi);
    phi[std::min(bins - 1, static_cast<int>(p * bins))]++;
  }
  // 15 degrees of freedom: the 0.999 quantile is 37.7.
  EXPECT_LT(chi_square_uniform(c2, n), 37.7);
  EXPECT_LT(chi_square_uniform(phi, n), 37.7);
}

// The GGX VNDF sampler and ggx_reflection_pdf must describe the same distribution: the fraction of samples
// falling into a cone equals the integral of the pdf over it (estimated with uniform directions in the cone).
TEST(Sampling, GgxVndfMatchesItsPdf) {
  for (float roughness : {0.2f, 0.5f, 0.9f}) {
    const float alpha = ggx_alpha(roughness);
    const Vec3 wo = normalize(Vec3{0.5f, 0.1f, 0.8f});
    const Vec3 axis = reflect(wo, Vec3{0, 0, 1});
    const float cos_cone = std::cos(0.35f);
    const int n = 200000;
    int inside = 0;
    for (int i = 0; i < n; ++i) {
      const Vec3 m = sample_ggx_vndf(wo, alpha, rng_float(3, 1, i, 0), rng_float(3, 1, i, 1));
      const Vec3 wi = reflect(wo, m);
      if (wi.z > 0 && dot(wi, axis) > cos_cone) ++inside;
    }
    // Integral of the pdf over the cone by uniform sampling of the cone's solid angle.
    const Frame f = make_frame(axis);
    const double solid_angle = 2 * kPi * (1 - cos_cone);
    double integral = 0;
    for (int i = 0; i < n; ++i) {
      const float z = 1 - rng_float(5, 2, i, 0) * (1 - cos_cone);
      const float r = std::sqrt(std::max(0.f, 1 - z * z));
      const float phi = 2 * kPi * rng_float(5, 2, i, 1);
      const Vec3 wi = f.to_world({r * std::cos(phi), r * std::sin(phi), z});
      integral += ggx_reflection_pdf(wo, wi, alpha);
    }
    integral *= solid_angle / n;
    const double fraction = static_cast<double>(inside) / n;
    EXPECT_NEAR(fraction, integral, 0.01 + 0.02 * fraction) << "roughness " << roughness;
  }
}

TEST(Sampling, SampledDirectionsAreFiniteForStiffInputs) {
  BsdfParams glossy;
  glossy.cls = MaterialClass::Glossy;
  int non_finite = 0;
  for (float rough : {0.f, 1e-4f, 0.5f, 1.f}) {
    glossy.roughness = rough;
    for (Vec3 n : {Vec3{0, 0, 1}, Vec3{0, 0, -1}, normalize(Vec3{0, 1e-8f, -1})}) {
      for (Vec3 wo : {n, normalize(n + Vec3{1, 0, 0} * 1e3f), normalize(Vec3{1, 0, 0})}) {
        for (int i = 0; i < 1000; ++i) {
          const DirectionSample s = sample_direction(glossy, n, n, wo, true, rng_float(1, 0, i, 0),
                                                     rng_float(1, 0, i, 1), rng_float(1, 0, i, 2));
          non_finite += !is_finite(s.dir) || !std::isfinite(s.pdf) || !is_finite(s.weight);
        }
      }
    }
  }
  EXPECT_EQ(non_finite, 0);
}

TEST(Sampling, BelowGeometricSurfaceIsFlaggedAndZeroWeighted) {
  BsdfParams diffuse;
  const Vec3 ng{0, 0, 1};
  const Vec3 ns = normalize(Vec3{0.9f, 0, 0.1f});  // shading normal tilted far from the geometric one
  int flagged = 0;
  for (int i = 0; i < 4000; ++i) {
    const DirectionSample s =
        sample_direction(diffuse, ns, ng, ng, true, rng_float(2, 0, i, 0), rng_float(2, 0, i, 1), 0.5f);
    if (dot(s.dir, ng) <= 0) {
      EXPECT_TRUE(s.flags & kSampleBelowGeometric);
      EXPECT_EQ(s.weight.x, 0.f);
      ++flagged;
    } else {
      EXPECT_FALSE(s.flags & kSampleBelowGeometric);
    }
  }
  EXPECT_GT(flagged, 0);
}

TEST(Offset, MovesOffTheSurfaceAtAnyScale) {
  for (float scale : {1e-6f, 1.f, 1e6f}) {
    const Vec3 p{0.3f * scale, -0.7f * scale, 0.2f * scale};
    const Vec3 n = normalize(Vec3{0.2f, 0.9f, -0.1f});
    const Vec3 q = offset_ray_origin(p, n);
    EXPECT_GT(dot(q - p, n), 0.f) << scale;
  }
}

TEST(Rng, DeterministicAndWellSpread) {
  EXPECT_EQ(rng_u32(1, 2, 3, 4), rng_u32(1, 2, 3, 4));
  EXPECT_NE(rng_u32(1, 2, 3, 4), rng_u32(1, 2, 3, 5));
  EXPECT_NE(rng_u32(1, 2, 3, 4), rng_u32(1, 2, 4, 4));
  EXPECT_NE(rng_u32(1, 2, 3, 4), rng_u32(1, 3, 3, 4));
  EXPECT_NE(rng_u32(1, 2, 3, 4), rng_u32(2, 2, 3, 4));
  const int n = 160000, bins = 16;
  std::vector<int> counts(bins, 0);
  for (int i = 0; i < n; ++i) {
    const float u = rng_float(9, 0, i, 0);
    ASSERT_GE(u, 0.f);
    ASSERT_LT(u, 1.f);
    counts[static_cast<int>(u * bins)]++;
  }
  EXPECT_LT(chi_square_uniform(counts, n), 37.7);
}

// Triangle test on hand-made cases: hits inside, misses outside, shared edges hit exactly once.
TEST(Traversal, WatertightOnSharedEdgesAndVertices) {
  // Two triangles sharing the diagonal of the unit square in the z = 0 plane.
  const BvhTriangle a{{0, 0, 0}, 0, {1, 0, 0}, 0, {1, 1, 0}, 0};
  const BvhTriangle b{{0, 0, 0}, 1, {1, 1, 0}, 0, {0, 1, 0}, 0};
  int missed = 0;
  for (int i = 0; i <= 64; ++i) {
    const float s = i / 64.f;
    Ray r;
    r.org = {s, s, 1};  // exactly above the shared diagonal, including both shared vertices
    r.dir = {0, 0, -1};
    const PreparedRay pr = prepare_ray(r);
    Hit h;
    const bool ha = intersect_triangle(pr, a, h);
    const bool hb = intersect_triangle(pr, b, h);
    missed += !(ha || hb);
    if (ha || hb) {
      EXPECT_FLOAT_EQ(h.t, 1.f);
    }
  }
  EXPECT_EQ(missed, 0);
  Ray r;
  r.org = {1.5f, 0.5f, 1};
  r.dir = {0, 0, -1};
  Hit h;
  EXPECT_FALSE(intersect_triangle(prepare_ray(r), a, h));
}

TEST(Traversal, BackFacesHitAndIntervalRespected) {
  const BvhTriangle tri{{-1, -1, 0}, 7, {1, -1, 0}, 0, {0, 1, 0}, 0};
  for (float dz : {-1.f, 1.f}) {
    Ray r;
    r.org = {0, 0, -dz * 2};
    r.dir = {0, 0, dz};
    Hit h;
    ASSERT_TRUE(intersect_triangle(prepare_ray(r), tri, h));
    EXPECT_FLOAT_EQ(h.t, 2.f);
    EXPECT_EQ(h.prim, 7u);
    Hit h2;
    r.tmax = 1.5f;
    h2.t = r.tmax;
    EXPECT_FALSE(intersect_triangle(prepare_ray(r), tri, h2));
  }
}

TEST(Traversal, DegenerateRaysDoNoWork) {
  BvhNode node{};
  node.lo0 = node.lo1 = {-1, -1, -1};
  node.hi0 = node.hi1 = {1, 1, 1};
  const BvhTriangle tri{{-1, -1, 0}, 0, {1, -1, 0}, 0, {0, 1, 0}, 0};
  node.child[0] = make_leaf_ref(0, 1);
  node.child[1] = make_leaf_ref(0, 0);
  const BvhView view{&node, &tri, 1, 1};
  const float nan = std::nanf("");
  const float inf = __builtin_huge_valf();
  for (Ray r : {Ray{{0, 0, 1}, 0, {0, 0, 0}, inf}, Ray{{nan, 0, 1}, 0, {0, 0, -1}, inf},
                Ray{{0, 0, 1}, 0, {0, 0, -1}, 0.f}, Ray{{0, 0, 1}, 0, {inf, 0, -1}, inf}}) {
    RayCounters c;
    const Hit h = closest_hit(view, r, c);
    EXPECT_FALSE(h.valid());
    EXPECT_EQ(c.nodes, 0u);
  }
  RayCounters c;
  const Hit h = closest_hit(view, Ray{{0.1f, 0, 1}, 0, {0, 0, -1}, inf}, c);
  EXPECT_TRUE(h.valid());
  EXPECT_EQ(c.nodes, 1u);
  EXPECT_EQ(c.leaves, 2u);  // the real leaf and the empty one
  EXPECT_EQ(c.triangles, 1u);
}

}  // namespace
}  // namespace raycoh
