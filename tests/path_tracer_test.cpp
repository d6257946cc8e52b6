// The path tracer (shading/path_tracer.h and its stages) against analytic answers (a sky-lit, a sun-lit and a
// glossy plane, thin glass, a closed emitting box), convergence and determinism on the built-in Cornell box, and
// the validation of its settings.
#include "shading/path_tracer.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>

#include "bvh/bvh_build.h"
#include "core/bsdf.h"
#include "core/error.h"
#include "generators/generator.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "shading/metrics.h"
#include "tests/shading_test_util.h"
#include "tests/test_util.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

using test::error_of;
using test::small;

// Appends a quad whose winding faces n (the emitting and "front" side).
void add_quad(Scene& s, Vec3 p0, Vec3 p1, Vec3 p2, Vec3 p3, Vec3 n, uint32_t material) {
  if (dot(cross(p1 - p0, p2 - p0), n) < 0.f) std::swap(p1, p3);
  const uint32_t base = static_cast<uint32_t>(s.positions.size());
  for (Vec3 p : {p0, p1, p2, p3}) {
    s.positions.push_back(p);
    s.normals.push_back(n);
  }
  s.indices.insert(s.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  s.tri_material.insert(s.tri_material.end(), {material, material});
}

Material diffuse(Vec3 albedo, Vec3 emission = Vec3(0.f)) {
  Material m;
  m.name = "m";
  m.base_color = albedo;
  m.roughness = 1.f;
  m.emission = emission;
  m.cls = classify_material(m);
  return m;
}

// A huge diffuse floor at y = 0 seen from 1 unit above, looking 45 degrees down: every camera ray hits it, and
// nothing but the environment is above it.
Scene open_floor(Vec3 albedo) {
  Scene s;
  s.name = "floor";
  s.source = "test";
  s.materials = {diffuse(albedo)};
  const float e = 1000.f;
  add_quad(s, {-e, 0.f, -e}, {e, 0.f, -e}, {e, 0.f, e}, {-e, 0.f, e}, {0.f, 1.f, 0.f}, 0);
  s.camera.eye = {0.f, 1.f, 0.f};
  s.camera.target = {0.f, 0.f, -1.f};
  s.camera.up = {0.f, 1.f, 0.f};
  s.camera.vfov_deg = 30.f;
  s.camera.from_file = true;
  finalize_scene(s);
  return s;
}

struct Rendered {
  Image image;
  FrameStats stats;
  uint64_t non_finite = 0;
};

Rendered render(const Scene& scene, const std::string& generator, RenderSettings rs, int frames,
                const std::string& tracer = "cpu") {
  const Bvh bvh = build_bvh(scene);
  auto tr = make_tracer(parse_plugin_spec(tracer), scene, bvh);
  auto gen = make_generator(parse_plugin_spec(generator));
  PathTracer pt(scene, *tr, *gen, rs);
  Accumulator acc(rs.width, rs.height);
  Rendered out;
  out.stats = pt.render_frames(0, frames, acc);
  out.image = acc.mean();
  out.non_finite = acc.non_finite_samples();
  return out;
}
TEST(PathTracer, UniformSkyOverADiffuseFloorGivesAlbedoTimesSky) {
  // Lambertian floor under a uniform sky of radiance c with nothing in the way: L = (a / pi) * pi c = a c for
  // every sample (cosine sampling makes the estimator exact).
  Scene s = open_floor({0.5f, 0.6f, 0.7f});
  ASSERT_TRUE(s.env.enabled);
  s.env.sun_radiance = Vec3(0.f);
  s.env.sky_zenith = s.env.sky_horizon = {0.3f, 0.4f, 0.5f};
  const Rendered r = render(s, "noopt", small(24, 16), 2);
  EXPECT_EQ(r.non_finite, 0u);
  for (size_t p = 0; p < r.image.pixels(); ++p) {
    EXPECT_NEAR(r.image.at(p).x, 0.15f, 1e-6f);
    EXPECT_NEAR(r.image.at(p).y, 0.24f, 1e-6f);
    EXPECT_NEAR(r.image.at(p).z, 0.35f, 1e-6f);
  }
  EXPECT_EQ(r.stats.shadow_rays, 0u);  // no emitter and no sun: nothing to sample
  EXPECT_EQ(r.stats.secondary_rays, 2u * 24 * 16);
}

TEST(PathTracer, SunOverADiffuseFloorMatchesTheIrradianceIntegral) {
  // Sun disc of radiance S and solid angle 2 pi (1 - cos_max) at elevation cos theta: L = a / pi S Omega cos theta.
  Scene s = open_floor({0.5f, 0.5f, 0.5f});
  s.env.sky_zenith = s.env.sky_horizon = Vec3(0.f);
  s.env.sun_radiance = Vec3(1000.f);
  const double omega = 2.0 * M_PI * (1.0 - static_cast<double>(s.env.sun_cos_half_angle));
  const double expected = 0.5 / M_PI * 1000.0 * omega * s.env.sun_dir.y;
  const Rendered r = render(s, "noopt", small(24, 16), 4);
  double sum = 0;
  for (size_t p = 0; p < r.image.pixels(); ++p) sum += r.image.at(p).y;
  EXPECT_NEAR(sum / static_cast<double>(r.image.pixels()), expected, 2e-3 * expected);
  EXPECT_GT(r.stats.shadow_rays, 0u);
}

TEST(PathTracer, GlossyFloorUnderAWideSunMatchesQuadrature) {
  // A GGX metal floor seen along one direction (tiny field of view) under a sun widened to 10 degrees, so that
  // NEE (cone sampling) and BSDF sampling both matter and MIS must combine them right: the mean must equal
  // S * integral over the cone of f cos, computed here by quadrature with the BSDF's own evaluation.
  Material metal = diffuse({0.9f, 0.8f, 0.7f});
  metal.roughness = 0.2f;
  metal.metallic = 1.f;
  metal.cls = classify_material(metal);
  ASSERT_EQ(metal.cls, MaterialClass::Glossy);
  Scene s = open_floor(Vec3(0.5f));
  s.materials[0] = metal;
  s.env.sky_zenith = s.env.sky_horizon = Vec3(0.f);
  s.env.sun_radiance = Vec3(2.f);
  s.env.sun_dir = normalize(Vec3{0.3f, 0.8f, 0.1f});
  s.env.sun_cos_half_angle = std::cos(10.f * kPi / 180.f);
  const Vec3 wo = normalize(Vec3{-0.25f, 0.8f, -0.2f});  // near the sun's mirror direction
  s.camera.eye = wo * 2.f;
  s.camera.target = Vec3(0.f);
  s.camera.vfov_deg = 0.01f;

  const BsdfParams m = bsdf_params(metal);
  const Vec3 n{0.f, 1.f, 0.f};
  const Frame sun = make_frame(s.env.sun_dir);
  const double theta_max = std::acos(static_cast<double>(s.env.sun_cos_half_angle));
  const int steps = 600;
  double expected = 0;
  for (int i = 0; i < steps; ++i)
    for (int j = 0; j < steps; ++j) {
      const double th = (i + 0.5) / steps * theta_max, ph = (j + 0.5) / steps * 2.0 * M_PI;
      const Vec3 wi = sun.to_world({static_cast<float>(std::sin(th) * std::cos(ph)),
                                    static_cast<float>(std::sin(th) * std::sin(ph)), static_cast<float>(std::cos(th))});
      const DirectionSample e = evaluate_direction(m, n, n, wo, normalize(wi));
      expected += e.weight.y * e.pdf * std::sin(th) * (theta_max / steps) * (2.0 * M_PI / steps);
    }
  expected *= 2.0;
  ASSERT_GT(expected, 0.05);
  const Rendered r = render(s, "noopt", small(16, 16), 64);
  double sum = 0;
  for (size_t p = 0; p < r.image.pixels(); ++p) sum += r.image.at(p).y;
  EXPECT_NEAR(sum / static_cast<double>(r.image.pixels()), expected, 0.02 * expected);
  EXPECT_EQ(r.non_finite, 0u);
}

TEST(PathTracer, ThinGlassOverAUniformSkyIsInvisible) {
  // A clear thin-walled pane reflects with weight 1 or passes straight through with weight 1 (white base):
  // under a uniform sky every sample is the sky's radiance.
  Material glass = diffuse(Vec3(1.f));
  glass.transmission = 1.f;
  glass.roughness = 0.f;
  glass.cls = classify_material(glass);
  ASSERT_EQ(glass.cls, MaterialClass::Transmissive);
  Scene s = open_floor(Vec3(0.5f));
  s.materials[0] = glass;
  s.env.sun_radiance = Vec3(0.f);
  s.env.sky_zenith = s.env.sky_horizon = {0.2f, 0.3f, 0.4f};
  const Rendered r = render(s, "noopt", small(16, 12), 4);
  for (size_t p = 0; p < r.image.pixels(); ++p) EXPECT_NEAR(r.image.at(p).z, 0.4f, 1e-6f);
  EXPECT_EQ(r.stats.shadow_rays, 0u);  // delta lobes get no next-event estimation
}

TEST(PathTracer, SunlightReachesAFloorThroughAThinPane) {
  // The sun-lit floor under a clear thin-walled pane: shadow rays go on through the pane, attenuated by its
  // straight-through transmittance 1 - F(cos theta). With max depth 2 no light bounces between floor and pane,
  // so L = a / pi S Omega cos theta (1 - F).
  Scene s = open_floor({0.5f, 0.5f, 0.5f});
  Material glass = diffuse(Vec3(1.f));
  glass.transmission = 1.f;
  glass.roughness = 0.f;
  glass.cls = classify_material(glass);
  s.materials.push_back(glass);
  const float e = 1000.f;
  add_quad(s, {-e, 0.5f, -e}, {e, 0.5f, -e}, {e, 0.5f, e}, {-e, 0.5f, e}, {0.f, 1.f, 0.f}, 1);
  s.camera.eye = {0.f, 0.25f, 0.f};
  s.camera.target = {0.f, 0.f, -0.5f};
  finalize_scene(s);
  s.env.sky_zenith = s.env.sky_horizon = Vec3(0.f);
  s.env.sun_radiance = Vec3(1000.f);
  const double cos_sun = s.env.sun_dir.y;
  const double omega = 2.0 * M_PI * (1.0 - static_cast<double>(s.env.sun_cos_half_angle));
  const double expected =
      0.5 / M_PI * 1000.0 * omega * cos_sun * (1.0 - fresnel_dielectric(static_cast<float>(cos_sun), glass.ior));
  RenderSettings rs = small(20, 16);
  rs.max_depth = 2;
  const Rendered r = render(s, "noopt", rs, 8);
  double sum = 0;
  for (size_t p = 0; p < r.image.pixels(); ++p) sum += r.image.at(p).y;
  EXPECT_NEAR(sum / static_cast<double>(r.image.pixels()), expected, 3e-3 * expected);
  // Without a pane to cross (max depth 1), the pane blocks the sun: NEE and BSDF sampling agree on that too.
  rs.max_depth = 1;
  const Rendered blocked = render(s, "noopt", rs, 2);
  double bsum = 0;
  for (size_t p = 0; p < blocked.image.pixels(); ++p) bsum += blocked.image.at(p).y;
  EXPECT_LT(bsum / static_cast<double>(blocked.image.pixels()), 1e-3 * expected);
}

TEST(PathTracer, ClosedEmittingBoxConvergesToTheGeometricSeries) {
  // Inside a closed box whose walls all emit Le = 1 and reflect with albedo a, a path of at most D scattering
  // events carries L = sum_{k=0..D} a^k. Exercises emitter NEE, MIS with BSDF hits (the weights must sum to one)
  // and Russian roulette (which must not bias).
  Scene s;
  s.name = "furnace";
  s.source = "test";
  s.materials = {diffuse(Vec3(0.5f), Vec3(1.f))};
  const float e = 1.f;
  add_quad(s, {-e, -e, -e}, {e, -e, -e}, {e, -e, e}, {-e, -e, e}, {0.f, 1.f, 0.f}, 0);
  add_quad(s, {-e, e, -e}, {e, e, -e}, {e, e, e}, {-e, e, e}, {0.f, -1.f, 0.f}, 0);
  add_quad(s, {-e, -e, -e}, {-e, e, -e}, {-e, e, e}, {-e, -e, e}, {1.f, 0.f, 0.f}, 0);
  add_quad(s, {e, -e, -e}, {e, e, -e}, {e, e, e}, {e, -e, e}, {-1.f, 0.f, 0.f}, 0);
  add_quad(s, {-e, -e, -e}, {e, -e, -e}, {e, e, -e}, {-e, e, -e}, {0.f, 0.f, 1.f}, 0);
  add_quad(s, {-e, -e, e}, {e, -e, e}, {e, e, e}, {-e, e, e}, {0.f, 0.f, -1.f}, 0);
  s.camera.eye = {0.2f, -0.1f, 0.3f};
  s.camera.target = {0.f, 0.f, -1.f};
  s.camera.from_file = true;
  s.camera.vfov_deg = 90.f;
  finalize_scene(s);
  ASSERT_FALSE(s.env.enabled);
  ASSERT_EQ(s.emissive_tris.size(), 12u);
  for (int depth : {1, 5}) {
    RenderSettings rs = small(32, 32);
    rs.max_depth = depth;
    rs.rr_depth = 2;
    const Rendered r = render(s, "noopt", rs, 24);
    double expected = 0, ak = 1;
    for (int k = 0; k <= depth; ++k, ak *= 0.5) expected += ak;
    double sum = 0;
    for (size_t p = 0; p < r.image.pixels(); ++p) sum += r.image.at(p).x + r.image.at(p).y + r.image.at(p).z;
    EXPECT_NEAR(sum / (3.0 * static_cast<double>(r.image.pixels())), expected, 0.005 * expected) << "depth " << depth;
    EXPECT_EQ(r.non_finite, 0u);
  }
}

TEST(PathTracer, CornellBoxIsFiniteAndConverges) {
  const Scene s = load_scene("cornell");
  const Rendered ref = render(s, "noopt", small(48, 36, 99), 256);
  const Rendered r8 = render(s, "noopt", small(48, 36, 1), 8);
  const Rendered r64 = render(s, "noopt", small(48, 36, 1), 64);
  for (const Rendered* r : {&ref, &r8, &r64}) {
    EXPECT_EQ(r->non_finite, 0u);
    EXPECT_EQ(count_non_finite(r->image).nan_pixels + count_non_finite(r->image).inf_pixels, 0u);
  }
  double mean = 0;
  for (float v : ref.image.rgb) mean += v;
  mean /= static_cast<double>(ref.image.rgb.size());
  EXPECT_GT(mean, 0.05);
  EXPECT_LT(mean, 5.0);
  EXPECT_LT(mse(r64.image, ref.image), mse(r8.image, ref.image));
  EXPECT_LT(rel_mse(r64.image, ref.image), rel_mse(r8.image, ref.image));
  EXPECT_GT(psnr(r64.image, ref.image), psnr(r8.image, ref.image));
  // Rays: one camera ray per pixel, one secondary ray per hit pixel (the open front shows black background).
  EXPECT_EQ(r8.stats.primary_rays, 8u * 48 * 36);
  EXPECT_GT(r8.stats.shadow_rays, 0u);
  EXPECT_GT(r8.stats.bounce_rays, 0u);
  EXPECT_GT(r8.stats.trace_s, 0.0);
  EXPECT_GE(r8.stats.wall_s, r8.stats.trace_s);
}

TEST(PathTracer, OursStaysCloseToNoOptOnCornell) {
  const Scene s = load_scene("cornell");
  const Rendered ref = render(s, "noopt", small(48, 36, 99), 128);
  const Rendered noopt = render(s, "noopt", small(48, 36, 1), 32);
  const Rendered ours = render(s, "ours", small(48, 36, 1), 32);
  EXPECT_EQ(ours.non_finite, 0u);
  EXPECT_GT(ours.stats.generation.reused_rays, 0u);
  EXPECT_NEAR(psnr(ours.image, ref.image), psnr(noopt.image, ref.image), 3.0);
}

TEST(PathTracer, SameSeedGivesTheSameBitsForOneAndTwoThreads) {
  const Scene s = load_scene("cornell");
  for (const char* gen : {"noopt", "ours"}) {
    Image one, two;
    {
      tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
      one = render(s, gen, small(40, 30, 7), 3).image;
    }
    {
      tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
      two = render(s, gen, small(40, 30, 7), 3).image;
    }
    ASSERT_EQ(one.rgb.size(), two.rgb.size());
    EXPECT_EQ(std::memcmp(one.rgb.data(), two.rgb.data(), one.rgb.size() * sizeof(float)), 0) << gen;
    const Image other = render(s, gen, small(40, 30, 8), 3).image;
    EXPECT_NE(std::memcmp(one.rgb.data(), other.rgb.data(), one.rgb.size() * sizeof(float)), 0) << gen;
  }
}

TEST(PathTracer, EmbreeTracerRendersTheSameImage) {
  const Scene s = load_scene("cornell");
  const Image a = render(s, "noopt", small(32, 24), 2, "cpu").image;
  const Image b = render(s, "noopt", small(32, 24), 2, "embree").image;
  EXPECT_LT(rmse(a, b), 0.05);
}

TEST(PathTracer, BadSettingsAreErrors) {
  RenderSettings rs;
  rs.max_depth = 0;
  EXPECT_NE(error_of([&] { rs.validate(); }).find("max depth"), std::string::npos);
  rs = RenderSettings{};
  rs.width = 0;
  EXPECT_THROW(rs.validate(), Error);
}
}  // namespace
}  // namespace raycoh
