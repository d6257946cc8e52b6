// The prior-art generators `sadeghi` and `microjitter` (generators/shared_sample.cpp): each pixel's marginal
// direction is its BSDF's (the same goodness-of-fit test as `ours`, tests/reuse_test.cpp), pixels share their
// random numbers as documented (one stream per frame, N x N interleaved streams, a jitter within the radius),
// and parameters are checked.
#include "generators/shared_sample.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "core/rng.h"
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

// ---- the batches pinned: the CPU generators' output recorded before the numbers rule became shared with the
// device kernel (generators/shared_sample.h), on a synthetic G-buffer of every material class with holes ----

Scene mixed_scene() {
  Scene s;
  s.name = "mixed";
  Material d, g, sp, t;
  d.cls = MaterialClass::Diffuse;
  g.cls = MaterialClass::Glossy;
  g.roughness = 0.3f;
  g.metallic = 1.f;
  sp.cls = MaterialClass::Specular;
  sp.roughness = 0.02f;
  t.cls = MaterialClass::Transmissive;
  t.transmission = 1.f;
  s.materials = {d, g, sp, t};
  return s;
}

// 21 x 13 (partial tiles), every 7th pixel without a hit, normals tilted per pixel, materials cycling.
GBuffer mixed_gbuffer(uint32_t frame) {
  GBuffer g = gbuffer(21, 13, true);
  g.frame = frame;
  g.hits = 0;
  for (size_t i = 0; i < g.points.size(); ++i) {
    ShadingPoint& p = g.points[i];
    p.material = static_cast<uint32_t>(i * 5 / 3 % 4);
    p.cls = mixed_scene().materials[p.material].cls;
    p.front_face = i % 5 != 0;
    if (i % 7 == 3) p.prim = kNoHit;
    g.hits += p.valid();
  }
  return g;
}

uint64_t fnv(uint64_t h, const void* data, size_t bytes) {
  const auto* b = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < bytes; ++i) h = (h ^ b[i]) * 0x100000001b3ull;
  return h;
}

// FNV-1a of every column and the statistics of each spec's batch at frames 0 and 5, seed 7.
uint64_t batches_checksum(const std::vector<std::string>& specs) {
  uint64_t h = 0xcbf29ce484222325ull;
  const Scene scene = mixed_scene();
  for (const std::string& spec : specs)
    for (uint32_t frame : {0u, 5u}) {
      RayBatch b;
      GenerationStats st;
      make_generator(parse_plugin_spec(spec))->generate(scene, mixed_gbuffer(frame), 7, b, st);
#define RAYCOH_HASH_COLUMN(name, T, grouped) h = fnv(h, b.name.data(), b.name.size() * sizeof(T));
      RAYCOH_BATCH_COLUMNS(RAYCOH_HASH_COLUMN)
#undef RAYCOH_HASH_COLUMN
      const uint64_t counts[] = {st.rays, st.below_geometric, st.below_shading, st.non_finite, st.reused_rays};
      h = fnv(h, counts, sizeof(counts));
    }
  return h;
}

TEST(SharedSample, BatchesEqualThoseRecordedBeforeTheRuleWasShared) {
  const uint64_t sadeghi = batches_checksum(
      {"sadeghi", "sadeghi:interleave=4", "sadeghi:interleave=3,order=scanline", "sadeghi:interleave=17,tile=4x4"});
  const uint64_t microjitter = batches_checksum({"microjitter", "microjitter:radius=0.5,tile=16x4",
                                                 "microjitter:radius=1,order=scanline", "microjitter:radius=0"});
  // Recorded by running the generators as they were before generators/shared_sample.h (commit 3fa2473).
  EXPECT_EQ(sadeghi, 0x1a73bea2e5a2b0f1ull) << std::hex << sadeghi;
  EXPECT_EQ(microjitter, 0xb2362e0fe8815775ull) << std::hex << microjitter;
}

// The shared rule (generators/shared_sample.h) against the rule written out here as the papers state it: the
// batch's every ray is its pixel's BSDF sampled with those numbers, and the reused count is every ray unless
// each pixel has its own stream.
void expect_reference_rule(const std::string& spec, const SharedSampleConfig& c) {
  SCOPED_TRACE(spec);
  const Scene scene = mixed_scene();
  const GBuffer g = mixed_gbuffer(2);
  RayBatch b;
  GenerationStats st;
  auto generator = make_generator(parse_plugin_spec(spec));
  generator->generate(scene, g, 11, b, st);
  const DeviceRecipe r = generator->device_recipe();
  ASSERT_EQ(r.kind, DeviceRecipe::Kind::SharedSample);
  EXPECT_EQ(r.shared.sharing, c.sharing);
  EXPECT_EQ(r.shared.interleave, c.interleave);
  EXPECT_EQ(r.shared.radius, c.radius);
  ASSERT_EQ(b.size(), g.hits);
  const uint32_t dims[3] = {kDimSecondary0, kDimSecondary1, kDimSecondaryLobe};
  for (size_t i = 0; i < b.size(); ++i) {
    const uint32_t p = b.pixel[i], x = p % 21, y = p / 21;
    float u[3], v[3];
    for (int d = 0; d < 3; ++d) {
      if (c.sharing == Sharing::Sadeghi) {
        u[d] = rng_float(11, 2, 0xF0000000u + (y % c.interleave) * c.interleave + x % c.interleave, dims[d]);
      } else {
        const float t = rng_float(11, 2, 0xF0000000u, dims[d]) + c.radius * (rng_float(11, 2, p, dims[d]) - 0.5f);
        u[d] = std::min(t - std::floor(t), 0x1.fffffep-1f);
      }
    }
    shared_sample_numbers(c, 11, 2, x, y, p, v);
    ASSERT_EQ(std::memcmp(u, v, sizeof(u)), 0) << "pixel " << p;
    for (float n : v) ASSERT_TRUE(n >= 0.f && n < 1.f) << n;
    const ShadingPoint& sp = g.points[p];
    const DirectionSample s = sample_direction(bsdf_params(scene.materials[sp.material]), sp.ns, sp.ng, sp.wo,
                                               sp.front_face, u[0], u[1], u[2]);
    ASSERT_EQ(std::memcmp(&s.dir, &b.rays[i].dir, sizeof(Vec3)), 0) << "pixel " << p;
    ASSERT_EQ(std::memcmp(&s.pdf, &b.pdf[i], sizeof(float)), 0) << "pixel " << p;
  }
  EXPECT_EQ(st.reused_rays, shared_sample_all_own(c, 21, 13) ? 0u : b.size());
}

TEST(SharedSample, TheSharedRuleIsThePapersRule) {
  expect_reference_rule("sadeghi", {Sharing::Sadeghi, 1, 0.f});
  expect_reference_rule("sadeghi:interleave=4", {Sharing::Sadeghi, 4, 0.f});
  expect_reference_rule("sadeghi:interleave=17", {Sharing::Sadeghi, 17, 0.f});  // 289 >= 273 pixels: all own
  expect_reference_rule("microjitter", {Sharing::MicroJitter, 1, 0.05f});
  expect_reference_rule("microjitter:radius=1", {Sharing::MicroJitter, 1, 1.f});
  EXPECT_FALSE(shared_sample_all_own({Sharing::Sadeghi, 16, 0.f}, 21, 13));
  EXPECT_TRUE(shared_sample_all_own({Sharing::Sadeghi, 65536, 0.f}, 65536, 65536));
  EXPECT_FALSE(shared_sample_all_own({Sharing::MicroJitter, 65536, 1.f}, 1, 1));
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
