// Rendering and image quality: accumulation with NaN/Inf counting, tone map, crops, image files, the error
// metrics (SSIM against scikit-image), the path tracer against analytic answers (a sky-lit and a sun-lit plane,
// a closed emitting box), convergence and determinism on the built-in Cornell box, the reference cache's
// invalidation, and the quality commands' validation, CSV and resume.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <fstream>

#include "core/error.h"
#include "bvh/bvh_build.h"
#include "tracers/tracer.h"
#include "generators/generator.h"
#include "harness/quality.h"
#include "shading/image.h"
#include "shading/metrics.h"
#include "shading/path_tracer.h"
#include "shading/reference.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

namespace fs = std::filesystem;

using test::error_of;

Image filled(int w, int h, Vec3 v) { return Image(w, h, v); }

// ---------------------------------------------------------------------------------------------------------------
// Images, accumulation, tone map, crops, files

TEST(Accumulator, CountsNonFiniteSamplesInsteadOfAddingThem) {
  Accumulator acc(2, 1);
  acc.add(0, {1.f, 2.f, 3.f});
  acc.add(0, {3.f, 2.f, 1.f});
  acc.add(0, {NAN, 0.f, 0.f});
  acc.add(1, {INFINITY, 0.f, 0.f});
  acc.add(1, {0.f, -INFINITY, 0.f});
  const Image m = acc.mean();
  EXPECT_EQ(m.at(0).x, 2.f);
  EXPECT_EQ(m.at(0).y, 2.f);
  EXPECT_EQ(m.at(0).z, 2.f);
  EXPECT_EQ(m.at(1).x, 0.f);  // no finite sample: 0, not NaN
  EXPECT_EQ(acc.non_finite_samples(), 3u);
  EXPECT_EQ(acc.non_finite_samples(0), 1u);
  EXPECT_EQ(acc.non_finite_samples(1), 2u);
  EXPECT_EQ(acc.pixels_with_non_finite(), 2u);
  EXPECT_EQ(acc.samples(0), 2u);
  for (float v : m.rgb) EXPECT_TRUE(std::isfinite(v));
}

TEST(ToneMap, MonotoneBoundedAndDefinedForNonFinite) {
  for (ToneMapKind kind : {ToneMapKind::Aces, ToneMapKind::Clamp}) {
    for (float exposure : {0.25f, 1.f, 4.f}) {
      const ToneMap tm{kind, exposure};
      float prev = -1.f;
      for (float x = 0.f; x < 200.f; x = x * 1.05f + 1e-4f) {
        const float y = tone_map_channel(x, tm);
        EXPECT_GE(y, prev) << "x " << x;
        EXPECT_GE(y, 0.f);
        EXPECT_LE(y, 1.f);
        prev = y;
      }
      EXPECT_EQ(tone_map_channel(0.f, tm), 0.f);
      EXPECT_EQ(tone_map_channel(-3.f, tm), 0.f);
      EXPECT_EQ(tone_map_channel(NAN, tm), 0.f);
      EXPECT_EQ(tone_map_channel(INFINITY, tm), 1.f);
    }
  }
  EXPECT_EQ(srgb_oetf(1.f), 1.f);
  EXPECT_NEAR(srgb_oetf(0.5f), 0.735357f, 1e-5f);   // IEC 61966-2-1
  EXPECT_NEAR(srgb_oetf(0.002f), 0.02584f, 1e-6f);  // linear segment
  EXPECT_THROW(parse_tone_map("filmic"), Error);
}

TEST(ToneMap, AutoExposureMapsTheLogAverageToMiddleGrey) {
  Image img(4, 1, Vec3(0.f));  // black pixels (background) do not count
  img.set(0, Vec3(0.01f));
  img.set(1, Vec3(1.f));
  const float e = auto_exposure(img);
  EXPECT_NEAR(e, 0.18f / 0.1f, 1e-4f);  // log-average of 0.01 and 1 is 0.1
  const ToneMap tm = resolved(ToneMap{ToneMapKind::Aces, 1.f, true}, img);
  EXPECT_FALSE(tm.auto_exposure);
  EXPECT_EQ(tm.exposure, e);
  EXPECT_EQ(resolved(ToneMap{ToneMapKind::Clamp, 2.f, false}, img).exposure, 2.f);
  EXPECT_EQ(auto_exposure(Image(3, 3, Vec3(0.f))), 1.f);
  EXPECT_NE(describe(ToneMap{ToneMapKind::Aces, 1.f, true}).find("exposure=auto"), std::string::npos);
}

TEST(Crop, ParsesValidatesAndCopies) {
  const Crop c = parse_crop("--crop", "1,2,3,4");
  EXPECT_EQ(c.x, 1);
  EXPECT_EQ(c.h, 4);
  EXPECT_NE(error_of([] { parse_crop("--crop", "1,2,3"); }).find("--crop"), std::string::npos);
  EXPECT_NE(error_of([] { parse_crop("--crop", "a,2,3,4"); }).find("--crop"), std::string::npos);
  EXPECT_NE(error_of([] {
              check_crop("--crop", {8, 0, 4, 4}, 10, 10);
            }).find("not inside the 10x10"),
            std::string::npos);
  EXPECT_NE(error_of([] { check_crop("--crop", {0, 0, 0, 4}, 10, 10); }).find("at least 1"), std::string::npos);
  EXPECT_NO_THROW(check_crop("--crop", {6, 6, 4, 4}, 10, 10));
  Image img(4, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) img.set(x, y, Vec3(static_cast<float>(10 * y + x)));
  const Image cr = crop(img, {1, 1, 2, 2});
  EXPECT_EQ(cr.width, 2);
  EXPECT_EQ(cr.at(0, 0).x, 11.f);
  EXPECT_EQ(cr.at(1, 1).x, 22.f);
}

Image test_pattern(int w, int h) {
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      img.set(x, y, {0.1f * static_cast<float>(x), 1e-3f * static_cast<float>(y * y), x == y ? 17.25f : 0.5f});
  img.set(0, 0, {1e-30f, 3.4e38f, 0.f});
  return img;
}

TEST(ImageFiles, PfmRoundTripIsBitExactAndBadFilesAreErrors) {
  const fs::path dir = test::temp_dir("pfm");
  const Image img = test_pattern(7, 5);
  write_image(img, (dir / "a.pfm").string());
  const Image back = read_image((dir / "a.pfm").string());
  ASSERT_EQ(back.width, 7);
  ASSERT_EQ(back.height, 5);
  EXPECT_EQ(std::memcmp(back.rgb.data(), img.rgb.data(), img.rgb.size() * sizeof(float)), 0);

  EXPECT_NE(error_of([&] { read_image((dir / "missing.pfm").string()); }).find("no such image file"),
            std::string::npos);
  test::write_file(dir / "trunc.pfm", "PF\n4 4\n-1.0\n0123");
  EXPECT_NE(error_of([&] { read_image((dir / "trunc.pfm").string()); }).find("truncated"), std::string::npos);
  test::write_file(dir / "bad.pfm", "P6\n4 4\n255\n");
  EXPECT_NE(error_of([&] { read_image((dir / "bad.pfm").string()); }).find("not a PFM"), std::string::npos);
  EXPECT_NE(error_of([&] { write_image(img, (dir / "a.tiff").string()); }).find("unknown image extension"),
            std::string::npos);
  EXPECT_NE(error_of([&] { check_output_image_path("--out", "x.jpg"); }).find("--out"), std::string::npos);
}

TEST(ImageFiles, ExrRoundTripIsBitExactAndPngIsWritten) {
  const fs::path dir = test::temp_dir("exr");
  const Image img = test_pattern(9, 6);
  if (!image_io_available()) {
    EXPECT_NE(error_of([&] { write_image(img, (dir / "a.exr").string()); }).find("RAYCOH_IMAGE_IO"), std::string::npos);
    GTEST_SKIP() << "built without image I/O";
  }
  write_image(img, (dir / "a.exr").string());
  const Image back = read_image((dir / "a.exr").string());
  ASSERT_EQ(back.width, 9);
  ASSERT_EQ(back.height, 6);
  EXPECT_EQ(std::memcmp(back.rgb.data(), img.rgb.data(), img.rgb.size() * sizeof(float)), 0);
  write_image(img, (dir / "a.png").string());
  EXPECT_GT(fs::file_size(dir / "a.png"), 50u);
  for (const auto& e : fs::directory_iterator(dir))  // no temporary file is left behind
    EXPECT_NE(e.path().filename().string()[0], '.') << e.path();
  test::write_file(dir / "broken.exr", "not an exr");
  EXPECT_THROW(read_image((dir / "broken.exr").string()), Error);
}

// ---------------------------------------------------------------------------------------------------------------
// Metrics

TEST(Metrics, ExactValuesOnHandMadeImages) {
  // 2x2, reference black, one test pixel white: linear squared errors 1 in 3 of 12 channel values.
  const Image ref = filled(2, 2, Vec3(0.f));
  Image test = ref;
  test.set(1, 0, Vec3(1.f));
  const ToneMap clamp{ToneMapKind::Clamp, 1.f};  // maps 0 -> 0 and 1 -> 1 exactly
  EXPECT_DOUBLE_EQ(mse(test, ref), 0.25);
  EXPECT_DOUBLE_EQ(rmse(test, ref), 0.5);
  EXPECT_NEAR(rel_mse(test, ref), 3.0 * (1.0 / 0.01) / 12.0, 1e-12);
  EXPECT_NEAR(psnr(test, ref, clamp), 10.0 * std::log10(1.0 / 0.25), 1e-12);  // 6.0206 dB
  EXPECT_TRUE(std::isinf(psnr(ref, ref, clamp)));
  EXPECT_DOUBLE_EQ(mse(ref, ref), 0.0);

  // relMSE is relative: the same relative error on a bright and a dim image gives about the same value.
  const Image dim = filled(3, 3, Vec3(1.f)), bright = filled(3, 3, Vec3(100.f));
  const double r1 = rel_mse(filled(3, 3, Vec3(1.1f)), dim), r2 = rel_mse(filled(3, 3, Vec3(110.f)), bright);
  EXPECT_NEAR(r1, 0.01 / 1.01, 1e-6);
  EXPECT_NEAR(r2, 0.01, 1e-5);
}

TEST(Metrics, SizeMismatchAndEmptyImagesAreErrors) {
  const Image a = filled(16, 12, Vec3(0.5f)), b = filled(12, 16, Vec3(0.5f));
  const std::string msg = error_of([&] { mse(a, b); });
  EXPECT_NE(msg.find("16x12"), std::string::npos) << msg;
  EXPECT_NE(msg.find("12x16"), std::string::npos) << msg;
  EXPECT_THROW(rmse(a, b), Error);
  EXPECT_THROW(rel_mse(a, b), Error);
  EXPECT_THROW(psnr(a, b), Error);
  EXPECT_THROW(ssim(a, b), Error);
  EXPECT_THROW(compare_images(a, b), Error);
  EXPECT_THROW(mse(Image(), Image()), Error);
  EXPECT_NE(error_of([] { ssim(filled(10, 30, Vec3(0.f)), filled(10, 30, Vec3(0.f))); }).find("11x11"),
            std::string::npos);
  EXPECT_TRUE(std::isnan(compare_images(filled(4, 4, Vec3(0.f)), filled(4, 4, Vec3(0.f))).ssim));
}

TEST(Metrics, NonFinitePixelsAreCountedAndLeftOut) {
  const Image ref = filled(12, 12, Vec3(0.25f));
  Image test = ref;
  test.set(3, 3, {NAN, 0.25f, 0.25f});
  test.set(4, 4, {INFINITY, 0.25f, 0.25f});
  const NonFiniteCount n = count_non_finite(test);
  EXPECT_EQ(n.nan_pixels, 1u);
  EXPECT_EQ(n.inf_pixels, 1u);
  const ErrorMetrics m = compare_images(test, ref);
  EXPECT_EQ(m.nan_pixels, 1u);
  EXPECT_EQ(m.inf_pixels, 1u);
  EXPECT_EQ(m.pixels_compared, 142u);
  EXPECT_EQ(m.mse, 0.0);
  EXPECT_TRUE(std::isfinite(m.ssim));
}

std::vector<double> gray(int w, int h, double (*f)(int, int)) {
  std::vector<double> v(static_cast<size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) v[static_cast<size_t>(y) * w + x] = f(x, y);
  return v;
}

// Reference values computed independently with scikit-image:
//   /usr/bin/python3 (Debian 12: numpy 1.24.2, scipy 1.10.1, python3-skimage 0.19.3)
//   skimage.metrics.structural_similarity(a, b, gaussian_weights=True, sigma=1.5, use_sample_covariance=False,
//                                         data_range=1.0)
// on float64 arrays of shape (h, w) with a[y][x], b[y][x] given by the same formulas as below.
TEST(Metrics, SsimMatchesScikitImage) {
  struct Case {
    int w, h;
    double (*a)(int, int);
    double (*b)(int, int);
    double expected;
  };
  const Case cases[] = {
      {16, 16, [](int x, int y) { return ((x * 7 + y * 13) % 17) / 16.0; },
       [](int x, int y) {
         return std::min(1.0, std::max(0.0, ((x * 7 + y * 13) % 17) / 16.0 + (((x * x + 3 * y) % 5) - 2) / 20.0));
       },
       0.9742238449621069},
      {23, 19, [](int x, int y) { return (x + y) / 40.0; },
       [](int x, int y) { return (x + y) / 40.0 * 0.8 + 0.1 * ((x * y) % 3) / 2.0; }, 0.7441923147281507},
      {32, 24, [](int x, int y) { return ((x / 4 + y / 4) % 2) * 0.9 + 0.05; }, [](int, int) { return 0.5; },
       0.004576300354071375},
      {11, 11, [](int x, int y) { return ((x * 3 + y * 5) % 11) / 10.0; },
       [](int x, int y) { return ((x * 5 + y * 3) % 11) / 10.0; }, -0.10923742690708699},
  };
  for (const Case& c : cases) {
    const double s = ssim_gray(gray(c.w, c.h, c.a), gray(c.w, c.h, c.b), c.w, c.h);
    EXPECT_NEAR(s, c.expected, 1e-12) << c.w << "x" << c.h;
  }
}

TEST(Metrics, SsimOfIdenticalImagesIsOneAndDropsWithNoise) {
  const Image a = test_pattern(40, 30);
  EXPECT_DOUBLE_EQ(ssim(a, a), 1.0);
  Image b = a;
  for (size_t i = 0; i < b.rgb.size(); ++i) b.rgb[i] += 0.05f * static_cast<float>((i * 7919) % 13) / 13.f;
  const double s = ssim(b, a);
  EXPECT_LT(s, 1.0);
  EXPECT_GT(s, 0.0);
}

// ---------------------------------------------------------------------------------------------------------------
// The path tracer against analytic answers

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

RenderSettings small(int w, int h, uint32_t seed = 1) {
  RenderSettings rs;
  rs.width = w;
  rs.height = h;
  rs.seed = seed;
  return rs;
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

// ---------------------------------------------------------------------------------------------------------------
// Reference cache

TEST(ReferenceCache, ReusedOnlyWhenEveryKeyFieldMatches) {
  const Scene s = load_scene("cornell");
  const Bvh bvh = build_bvh(s);
  const fs::path dir = test::temp_dir("refcache");
  ReferenceRequest req;
  req.scene_spec = "cornell";
  req.settings = small(24, 16, 5);
  req.frames = 3;
  req.cache_dir = dir.string();
  req.revision = "test-r1";

  const Reference first = get_reference(s, bvh, req);
  EXPECT_FALSE(first.from_cache);
  EXPECT_TRUE(fs::exists(first.path));
  const Reference again = get_reference(s, bvh, req);
  EXPECT_TRUE(again.from_cache);
  EXPECT_EQ(again.path, first.path);
  EXPECT_EQ(std::memcmp(again.image.rgb.data(), first.image.rgb.data(), first.image.rgb.size() * sizeof(float)), 0);

  auto changed = [&](auto&& edit) {
    ReferenceRequest r = req;
    edit(r);
    return get_reference(s, bvh, r);
  };
  EXPECT_FALSE(changed([](ReferenceRequest& r) { r.frames = 4; }).from_cache);
  EXPECT_FALSE(changed([](ReferenceRequest& r) { r.settings.width = 25; }).from_cache);
  EXPECT_FALSE(changed([](ReferenceRequest& r) { r.settings.height = 17; }).from_cache);
  EXPECT_FALSE(changed([](ReferenceRequest& r) { r.settings.seed = 6; }).from_cache);
  EXPECT_FALSE(changed([](ReferenceRequest& r) { r.settings.max_depth = 2; }).from_cache);
  EXPECT_FALSE(changed([](ReferenceRequest& r) { r.revision = "test-r2"; }).from_cache);
  EXPECT_FALSE(changed([](ReferenceRequest& r) { r.tracer = {"embree", ""}; }).from_cache);
  EXPECT_TRUE(get_reference(s, bvh, req).from_cache);  // the original entry is still there

  // A sidecar that does not describe the request (edited, corrupt or missing) means: render again.
  fs::path sidecar = first.path;
  sidecar.replace_extension(".json");
  ASSERT_TRUE(fs::exists(sidecar));
  std::ifstream in(sidecar);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("\"renderer_revision\": \"test-r1\""), std::string::npos) << text;
  test::write_file(sidecar, "{ not json");
  EXPECT_FALSE(get_reference(s, bvh, req).from_cache);
  EXPECT_TRUE(get_reference(s, bvh, req).from_cache);
  fs::remove(first.path);
  EXPECT_FALSE(get_reference(s, bvh, req).from_cache);

  EXPECT_NE(renderer_revision().find("r" + std::to_string(kRendererVersion) + "/"), std::string::npos);
  EXPECT_EQ(scene_fingerprint("cornell"), "builtin:cornell");
  EXPECT_THROW(scene_fingerprint("/no/such/scene.glb"), Error);
}

TEST(ReferenceCache, SceneFileFingerprintFollowsItsContent) {
  const fs::path dir = test::temp_dir("fingerprint");
  test::write_file(dir / "a.obj", "v 0 0 0\n");
  const std::string f1 = scene_fingerprint((dir / "a.obj").string());
  EXPECT_EQ(scene_fingerprint((dir / "a.obj").string()), f1);
  test::write_file(dir / "a.obj", "v 0 0 1\n");
  EXPECT_NE(scene_fingerprint((dir / "a.obj").string()), f1);
}

// ---------------------------------------------------------------------------------------------------------------
// Commands: validation, CSV, resume, curves

TEST(QualityCommands, DurationsAndCurveReadings) {
  EXPECT_DOUBLE_EQ(parse_duration("--time", "60s"), 60.0);
  EXPECT_DOUBLE_EQ(parse_duration("--time", "1.5m"), 90.0);
  EXPECT_DOUBLE_EQ(parse_duration("--time", "500ms"), 0.5);
  EXPECT_DOUBLE_EQ(parse_duration("--time", "2"), 2.0);
  for (const char* bad : {"0", "-5s", "abc", "10parsecs", "inf", ""})
    EXPECT_NE(error_of([&] { parse_duration("--time", bad); }).find("--time"), std::string::npos) << bad;

  // Error 1/t sampled at t = 1, 2, 4: log-linear interpolation is exact for power laws.
  const std::vector<CurvePoint> c = {{1, 1.0}, {2, 0.5}, {4, 0.25}};
  EXPECT_NEAR(error_at_time(c, 2.0), 0.5, 1e-12);
  EXPECT_NEAR(error_at_time(c, std::sqrt(2.0)), 1.0 / std::sqrt(2.0), 1e-12);
  EXPECT_TRUE(std::isnan(error_at_time(c, 0.5)));
  EXPECT_TRUE(std::isnan(error_at_time(c, 5.0)));
  EXPECT_NEAR(time_to_error(c, 0.5), 2.0, 1e-12);
  EXPECT_NEAR(time_to_error(c, 1.0 / std::sqrt(8.0)), std::sqrt(8.0), 1e-12);
  EXPECT_NEAR(time_to_error(c, 2.0), 1.0, 1e-12);  // reached by the first frame
  EXPECT_TRUE(std::isnan(time_to_error(c, 0.1)));
}

TEST(QualityCommands, BadOptionsNameTheOption) {
  const Provenance prov;
  // Each case edits a fresh default option set and expects an error naming the option.
  auto render_error = [&](auto&& edit) {
    RenderOptions o;
    edit(o);
    return error_of([&] { run_render(o, prov); });
  };
  auto quality_error = [&](auto&& edit) {
    QualityOptions o;
    edit(o);
    return error_of([&] { run_quality(o, prov); });
  };
  auto converge_error = [&](auto&& edit) {
    ConvergeOptions o;
    edit(o);
    return error_of([&] { run_converge(o, prov); });
  };
  EXPECT_NE(render_error([](RenderOptions& o) { o.frames = 0; }).find("--frames"), std::string::npos);
  EXPECT_NE(render_error([](RenderOptions& o) { o.crops = {{150, 100, 20, 30}}; }).find("--crop"), std::string::npos);
  EXPECT_NE(render_error([](RenderOptions& o) { o.out = "img.bmp"; }).find("--out"), std::string::npos);
  EXPECT_NE(render_error([](RenderOptions& o) {
              o.generator = {"nosuch", ""};
              o.out = "img.pfm";  // writable in every build
            }).find("valid generators"),
            std::string::npos);
  EXPECT_NE(quality_error([](QualityOptions& o) { o.ref_frames = -1; }).find("--ref-frames"), std::string::npos);
  EXPECT_NE(quality_error([](QualityOptions& o) { o.common.width = 8; }).find("--res"), std::string::npos);
  EXPECT_NE(quality_error([](QualityOptions& o) { o.reference = "/no/such/reference.exr"; }).find("--reference"),
            std::string::npos);
  EXPECT_NE(quality_error([](QualityOptions& o) { o.scenes = {"nosuchscene"}; }).find("--scenes"), std::string::npos);
  EXPECT_NE(quality_error([](QualityOptions& o) {
              o.generators = {{"noopt", ""}, {"noopt", ""}};
            }).find("twice"),
            std::string::npos);
  EXPECT_NE(converge_error([](ConvergeOptions& o) { o.time_s = 0; }).find("--time"), std::string::npos);
  EXPECT_NE(converge_error([](ConvergeOptions& o) {
              o.common.tracer = {"gpu", ""};
            }).find("--tracer"),
            std::string::npos);

  // A reference of the wrong size: a clear error naming both sizes.
  const fs::path dir = test::temp_dir("badref");
  write_image(filled(10, 10, Vec3(0.5f)), (dir / "ref.pfm").string());
  const std::string msg = quality_error([&](QualityOptions& o) {
    o.common.width = 16;
    o.common.height = 12;
    o.reference = (dir / "ref.pfm").string();
    o.out = (dir / "q.csv").string();
  });
  EXPECT_NE(msg.find("10x10"), std::string::npos) << msg;
  EXPECT_NE(msg.find("16x12"), std::string::npos) << msg;
  EXPECT_FALSE(fs::exists(dir / "q.csv.partial"));  // nothing measured, nothing left behind

  CompareOptions cmp;
  cmp.test = (dir / "ref.pfm").string();
  cmp.reference = (dir / "missing.pfm").string();
  EXPECT_NE(error_of([&] { run_compare(cmp); }).find("reference image"), std::string::npos);
  write_image(filled(12, 10, Vec3(0.5f)), (dir / "other.pfm").string());
  cmp.reference = (dir / "other.pfm").string();
  EXPECT_NE(error_of([&] { run_compare(cmp); }).find("sizes differ"), std::string::npos);
}

std::vector<std::string> read_lines(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

TEST(QualityCommands, QualityWritesRowsImagesAndResumes) {
  const fs::path dir = test::temp_dir("quality");
  QualityOptions q;
  q.common.width = 24;
  q.common.height = 16;
  q.frames = 2;
  q.ref_frames = 8;
  q.bias_renders = 2;
  q.cache_dir = (dir / "cache").string();
  q.out = (dir / "q.csv").string();
  q.crops = {{2, 2, 8, 6}};
  Provenance prov;
  prov.git_revision = "test";
  ASSERT_EQ(run_quality(q, prov), 0);
  const auto lines = read_lines(dir / "q.csv");
  ASSERT_EQ(lines.size(), 3u);  // header + noopt + ours
  EXPECT_EQ(lines[0].rfind("scene,scene_spec,", 0), 0u);
  EXPECT_NE(lines[1].find(",noopt,"), std::string::npos);
  EXPECT_NE(lines[2].find(",ours,"), std::string::npos);
  const std::string ext = image_io_available() ? ".png" : ".pfm";
  for (const char* f :
       {"cornell-reference", "cornell-noopt", "cornell-ours", "cornell-ours-crop0", "cornell-reference-crop0"})
    EXPECT_TRUE(fs::exists(dir / "q-images" / (std::string(f) + ext))) << f;
  EXPECT_FALSE(fs::exists(dir / "q.csv.partial"));

  // An interrupted run: its rows sit in the .partial file; the same command takes them and renders nothing.
  fs::rename(dir / "q.csv", dir / "q.csv.partial");
  std::ofstream(dir / "q.csv.partial", std::ios::app) << "cornell,cornell,32,torn";  // a torn last line
  ASSERT_EQ(run_quality(q, prov), 0);
  EXPECT_EQ(read_lines(dir / "q.csv"), lines);

  // Another revision does not reuse them.
  fs::rename(dir / "q.csv", dir / "q.csv.partial");
  prov.git_revision = "test2";
  ASSERT_EQ(run_quality(q, prov), 0);
  const auto redone = read_lines(dir / "q.csv");
  EXPECT_EQ(redone.size(), 5u);  // the old rows stay, two new ones follow
}

TEST(QualityCommands, ConvergeWritesCurvesAndRatios) {
  const fs::path dir = test::temp_dir("converge");
  ConvergeOptions c;
  c.common.width = 24;
  c.common.height = 16;
  c.time_s = 0.05;
  c.max_frames = 6;
  c.ref_frames = 8;
  c.cache_dir = (dir / "cache").string();
  c.out = (dir / "c.csv").string();
  ASSERT_EQ(run_converge(c, Provenance{}), 0);
  const auto rows = read_lines(dir / "c.csv");
  EXPECT_GE(rows.size(), 3u);
  EXPECT_LE(rows.size(), 13u);
  const auto summary = read_lines(dir / "c-summary.csv");
  ASSERT_EQ(summary.size(), 3u);  // header + ours (wall) + ours (trace)
  EXPECT_NE(summary[1].find(",wall,"), std::string::npos);
  EXPECT_NE(summary[2].find(",trace,"), std::string::npos);
}

TEST(QualityCommands, RenderWritesImageAndCrops) {
  const fs::path dir = test::temp_dir("render");
  RenderOptions r;
  r.common.width = 20;
  r.common.height = 14;
  r.frames = 2;
  r.out = (dir / "img.pfm").string();
  r.crops = {{0, 0, 5, 5}, {10, 4, 10, 10}};
  ASSERT_EQ(run_render(r, Provenance{}), 0);
  EXPECT_EQ(read_image((dir / "img.pfm").string()).width, 20);
  EXPECT_EQ(read_image((dir / "img-crop1.pfm").string()).width, 10);
  EXPECT_TRUE(fs::exists(dir / "img-crop0.pfm"));
}

}  // namespace
}  // namespace raycoh
