// The prior-art generators `sadeghi` and `microjitter` (generators/shared_sample.cpp): each pixel's marginal
// direction is its BSDF's (the same goodness-of-fit test as `ours`, tests/reuse_test.cpp), pixels share their
// random numbers as documented (one stream per frame, N x N interleaved streams, a jitter within the radius),
// and parameters are checked.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/sampling.h"
#include "generators/generator.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

Scene diffuse_scene() {
  Scene s;
  s.name = "diffuse";
  Material d;
  d.cls = MaterialClass::Diffuse;
  s.materials = {d};
  return s;
}

// A w x h G-buffer of diffuse points on the plane z = 0; with `tilted`, each pixel gets its own normal.
GBuffer gbuffer(int w, int h, bool tilted) {
  GBuffer g;
  g.width = w;
  g.height = h;
  g.points.resize(static_cast<size_t>(w) * h);
  for (size_t i = 0; i < g.points.size(); ++i) {
    ShadingPoint& p = g.points[i];
    p.position = {static_cast<float>(i % w), static_cast<float>(i / w), 0.f};
    p.ng = p.ns =
        tilted ? normalize(Vec3{0.6f * std::sin(1.7f * i), 0.6f * std::cos(2.3f * i), 1.f}) : Vec3{0.f, 0.f, 1.f};
    p.wo = normalize(Vec3{0.1f, 0.2f, 1.f});
    p.prim = static_cast<uint32_t>(i);
    p.material = 0;
    p.cls = MaterialClass::Diffuse;
  }
  g.hits = g.points.size();
  return g;
}

double chi2_uniform(const std::vector<int>& counts) {
  double total = 0;
  for (int c : counts) total += c;
  const double e = total / counts.size();
  double chi2 = 0;
  for (int c : counts) chi2 += (c - e) * (c - e) / e;
  return chi2;
}

// As Ours.EachDiffusePixelIsCosineDistributedAroundItsOwnNormal: over 3200 frames each of 64 pixels with its own
// tilted normal, u = cos^2(theta) and v = phi / 2pi in a 4 x 4 grid have equal expected counts.
class SharedSampleMarginal : public ::testing::TestWithParam<std::string> {};

TEST_P(SharedSampleMarginal, EachDiffusePixelIsCosineDistributedAroundItsOwnNormal) {
  const Scene scene = diffuse_scene();
  GBuffer g = gbuffer(8, 8, true);
  const int frames = 3200, bins = 4;
  std::vector<std::vector<int>> per_pixel(64, std::vector<int>(bins * bins, 0));
  auto generator = make_generator(parse_plugin_spec(GetParam()));
  RayBatch b;
  GenerationStats st;
  for (int f = 0; f < frames; ++f) {
    g.frame = static_cast<uint32_t>(f);
    generator->generate(scene, g, 42, b, st);
    ASSERT_EQ(b.size(), 64u);
    for (size_t i = 0; i < b.size(); ++i) {
      const Vec3 local = make_frame(g.points[b.pixel[i]].ns).to_local(b.rays[i].dir);
      ASSERT_GT(local.z, 0.f);
      const double u = local.z * local.z, v = (std::atan2(local.y, local.x) + kPi) / (2 * kPi);
      const int bu = std::min(bins - 1, static_cast<int>(u * bins)),
                bv = std::min(bins - 1, static_cast<int>(v * bins));
      ++per_pixel[b.pixel[i]][bu * bins + bv];
    }
  }
  // 15 degrees of freedom per pixel: 1e-4 upper quantile 47.0.
  for (int p = 0; p < 64; ++p) EXPECT_LT(chi2_uniform(per_pixel[p]), 47.0) << "pixel " << p;
}

INSTANTIATE_TEST_SUITE_P(Generators, SharedSampleMarginal,
                         ::testing::Values("sadeghi", "sadeghi:interleave=3", "microjitter", "microjitter:radius=0.5"),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string s = info.param;
                           for (char& c : s)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return s;
                         });

RayBatch run(const std::string& spec, const GBuffer& g) {
  RayBatch b;
  GenerationStats st;
  make_generator(parse_plugin_spec(spec))->generate(diffuse_scene(), g, 7, b, st);
  EXPECT_EQ(st.rays, b.size());
  return b;
}

TEST(Sadeghi, CoplanarPixelsShareOneDirectionPerStream) {
  GBuffer g = gbuffer(16, 12, false);
  g.frame = 3;
  const RayBatch one = run("sadeghi", g);
  for (size_t i = 1; i < one.size(); ++i) ASSERT_EQ(std::memcmp(&one.rays[0].dir, &one.rays[i].dir, sizeof(Vec3)), 0);
  // Interleaved: pixels with the same (x mod 4, y mod 4) share a direction, the 16 streams differ.
  const RayBatch four = run("sadeghi:interleave=4", g);
  std::vector<Vec3> dir_of(16, Vec3{0.f});
  std::vector<bool> seen(16, false);
  for (size_t i = 0; i < four.size(); ++i) {
    const uint32_t p = four.pixel[i], stream = (p / 16 % 4) * 4 + p % 16 % 4;
    if (!seen[stream]) {
      seen[stream] = true;
      dir_of[stream] = four.rays[i].dir;
    }
    EXPECT_EQ(std::memcmp(&dir_of[stream], &four.rays[i].dir, sizeof(Vec3)), 0) << "pixel " << p;
  }
  for (int a = 0; a < 16; ++a)
    for (int b = a + 1; b < 16; ++b) EXPECT_GT(length(dir_of[a] - dir_of[b]), 0.f);
  // A new frame draws new numbers.
  g.frame = 4;
  EXPECT_GT(length(run("sadeghi", g).rays[0].dir - one.rays[0].dir), 0.f);
}

TEST(MicroJitter, DirectionsStayWithinTheJitter) {
  GBuffer g = gbuffer(16, 16, false);
  const RayBatch tight = run("microjitter:radius=0.01", g);
  const RayBatch shared = run("microjitter:radius=0", g);
  float spread_tight = 0.f;
  for (size_t i = 0; i < tight.size(); ++i) {
    EXPECT_EQ(std::memcmp(&shared.rays[0].dir, &shared.rays[i].dir, sizeof(Vec3)), 0);
    spread_tight = std::max(spread_tight, length(tight.rays[i].dir - shared.rays[0].dir));
  }
  EXPECT_GT(spread_tight, 0.f);
  EXPECT_LT(spread_tight, 0.2f);  // within a 0.01 jitter of the shared sample (away from the torus seam)
}

TEST(SharedSample, ParametersAreChecked) {
  EXPECT_EQ(make_generator(parse_plugin_spec("sadeghi"))->params(), "order=tile,tile=8x8,interleave=1");
  EXPECT_EQ(make_generator(parse_plugin_spec("microjitter"))->params(), "order=tile,tile=8x8,radius=0.05");
  for (const char* spec : {"sadeghi:interleave=0", "sadeghi:radius=0.1", "microjitter:radius=2", "microjitter:k=4"}) {
    const std::string msg = test::error_of([&] { make_generator(parse_plugin_spec(spec)); });
    EXPECT_NE(msg.find("generator '"), std::string::npos) << spec << ": " << msg;
  }
}

}  // namespace
}  // namespace raycoh
