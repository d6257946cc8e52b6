// Pixel orders, primary rays, G-buffer and the NoOpt generator: structure, determinism for any thread count,
// and physically valid batches on the built-in scenes.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cstring>
#include <set>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "generators/primary.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

TEST(PixelOrder, IsAPermutationForAnyTileAndImage) {
  for (auto [w, h, tw, th] :
       std::vector<std::array<int, 4>>{{1, 1, 8, 8}, {13, 7, 8, 8}, {64, 64, 8, 8}, {5, 3, 16, 16}, {33, 17, 4, 8}}) {
    for (RayOrder order : {RayOrder::Scanline, RayOrder::Tile}) {
      std::vector<uint32_t> o = make_pixel_order(w, h, order, tw, th);
      ASSERT_EQ(o.size(), static_cast<size_t>(w * h));
      std::sort(o.begin(), o.end());
      for (size_t i = 0; i < o.size(); ++i) ASSERT_EQ(o[i], i);
    }
  }
}

TEST(PixelOrder, TileOrderKeepsTilesContiguous) {
  const auto o = make_pixel_order(16, 8, RayOrder::Tile, 8, 8);
  for (int i = 0; i < 64; ++i) EXPECT_LT(o[i] % 16, 8u);  // first tile: x < 8
  EXPECT_EQ(o[0], 0u);
  EXPECT_EQ(o[8], 16u);  // second row of the first tile
  EXPECT_EQ(o[64], 8u);  // first pixel of the second tile
  EXPECT_THROW(parse_ray_order("zigzag"), Error);
}

struct Frame0 {
  Scene scene;
  Bvh bvh;
  GBuffer gbuffer;
  explicit Frame0(const std::string& spec, int w = 96, int h = 64) : scene(load_scene(spec)), bvh(build_bvh(scene)) {
    const auto order = make_pixel_order(w, h, RayOrder::Tile, 8, 8);
    gbuffer = first_hits(scene, *make_tracer({"cpu", ""}, scene, bvh), w, h, order, 1, 0).gbuffer;
  }
};

RayBatch generate(const Frame0& f, const std::string& spec, uint32_t seed, GenerationStats* stats = nullptr) {
  RayBatch batch;
  GenerationStats s;
  make_generator(parse_plugin_spec(spec))->generate(f.scene, f.gbuffer, seed, batch, s);
  if (stats) *stats = s;
  return batch;
}

bool same_bytes(const RayBatch& a, const RayBatch& b) {
  return a.size() == b.size() && std::memcmp(a.rays.data(), b.rays.data(), a.size() * sizeof(Ray)) == 0 &&
         a.pixel == b.pixel && std::memcmp(a.pdf.data(), b.pdf.data(), a.size() * sizeof(float)) == 0 &&
         std::memcmp(a.weight.data(), b.weight.data(), a.size() * sizeof(Vec3)) == 0;
}

TEST(GBuffer, ShadingPointsAreConsistent) {
  const Frame0 f("cornell");
  EXPECT_GT(f.gbuffer.hits, f.gbuffer.points.size() / 2);  // the camera looks into the box
  for (const ShadingPoint& sp : f.gbuffer.points) {
    if (!sp.valid()) continue;
    EXPECT_GE(dot(sp.ng, sp.wo), 0.f);
    EXPECT_GE(dot(sp.ns, sp.ng), 0.f);
    EXPECT_NEAR(length(sp.ns), 1.f, 1e-4f);
    EXPECT_TRUE(is_finite(sp.position));
  }
}

TEST(FirstHits, EqualsPrimaryRaysTraceAndGBufferDoneByHand) {
  const Scene scene = load_scene("cornell");
  const Bvh bvh = build_bvh(scene);
  auto tracer = make_tracer({"cpu", ""}, scene, bvh);
  const auto order = make_pixel_order(40, 30, RayOrder::Tile, 8, 8);
  const FirstHits f = first_hits(scene, *tracer, 40, 30, order, 5, 2, false);
  const PixelRays primary = make_primary_rays(scene.camera, 40, 30, order, 5, 2, false);
  std::vector<Hit> hits(primary.rays.size());
  tracer->trace(primary.rays.data(), primary.rays.size(), hits.data());
  const GBuffer g = make_gbuffer(scene, primary, hits);
  ASSERT_EQ(f.primary.pixel, primary.pixel);
  ASSERT_EQ(f.hits.size(), hits.size());
  EXPECT_EQ(std::memcmp(f.primary.rays.data(), primary.rays.data(), hits.size() * sizeof(Ray)), 0);
  EXPECT_EQ(std::memcmp(f.hits.data(), hits.data(), hits.size() * sizeof(Hit)), 0);
  ASSERT_EQ(f.gbuffer.points.size(), g.points.size());
  EXPECT_EQ(f.gbuffer.hits, g.hits);
  EXPECT_EQ(f.gbuffer.frame, 2u);
  // Field by field: ShadingPoint has padding bytes, which memcmp would compare too.
  for (size_t i = 0; i < g.points.size(); ++i) {
    const ShadingPoint &a = f.gbuffer.points[i], &b = g.points[i];
    const bool same = std::memcmp(&a.position, &b.position, sizeof(Vec3)) == 0 &&
                      std::memcmp(&a.ng, &b.ng, sizeof(Vec3)) == 0 && std::memcmp(&a.ns, &b.ns, sizeof(Vec3)) == 0 &&
                      std::memcmp(&a.wo, &b.wo, sizeof(Vec3)) == 0 && a.prim == b.prim && a.material == b.material &&
                      a.cls == b.cls && a.front_face == b.front_face;
    ASSERT_TRUE(same) << "pixel " << i;
  }
  EXPECT_GE(f.trace_seconds, 0.0);
}

TEST(NoOpt, OneRayPerHitPixelInTileOrder) {
  const Frame0 f("cornell");
  const RayBatch b = generate(f, "noopt", 1);
  EXPECT_EQ(b.size(), f.gbuffer.hits);
  std::set<uint32_t> pixels(b.pixel.begin(), b.pixel.end());
  EXPECT_EQ(pixels.size(), b.size());
  const auto order = make_pixel_order(96, 64, RayOrder::Tile, 8, 8);
  std::vector<uint32_t> expected;
  for (uint32_t p : order)
    if (f.gbuffer.points[p].valid()) expected.push_back(p);
  EXPECT_EQ(b.pixel, expected);
  const RayBatch s = generate(f, "noopt:order=scanline", 1);
  EXPECT_TRUE(std::is_sorted(s.pixel.begin(), s.pixel.end()));
}

TEST(NoOpt, RaysAreValidAndLeaveTheSurface) {
  for (const char* spec : {"cornell", "voxels:size=24"}) {
    const Frame0 f(spec);
    GenerationStats stats;
    const RayBatch b = generate(f, "noopt", 3, &stats);
    EXPECT_EQ(stats.non_finite, 0u) << spec;
    for (size_t i = 0; i < b.size(); ++i) {
      ASSERT_TRUE(is_finite(b.rays[i].org) && is_finite(b.rays[i].dir)) << spec;
      ASSERT_NEAR(length(b.rays[i].dir), 1.f, 1e-4f);
      ASSERT_TRUE(std::isfinite(b.pdf[i]) && b.pdf[i] >= 0.f);
      const ShadingPoint& sp = f.gbuffer.points[b.pixel[i]];
      if (b.material[i] != MaterialClass::Transmissive && b.weight[i].x > 0.f) {
        ASSERT_GT(dot(b.rays[i].dir, sp.ng), 0.f);
      }
    }
  }
}

TEST(NoOpt, BatchesAreIdenticalForAnyThreadCountAndRepeatable) {
  const Frame0 f("voxels:size=24", 128, 96);
  RayBatch one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = generate(f, "noopt", 11);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = generate(f, "noopt", 11);
  }
  EXPECT_TRUE(same_bytes(one, two));
  EXPECT_TRUE(same_bytes(one, generate(f, "noopt", 11)));
  EXPECT_FALSE(same_bytes(one, generate(f, "noopt", 12)));
}

TEST(NoOpt, UnknownNamesAndParametersAreErrors) {
  EXPECT_THROW(make_generator({"nope", ""}), Error);
  EXPECT_THROW(make_generator({"noopt", "k=8"}), Error);
  EXPECT_THROW(make_generator({"noopt", "order=zigzag"}), Error);
  EXPECT_THROW(make_generator({"noopt", "tile=0x8"}), Error);
  EXPECT_EQ(make_generator({"noopt", ""})->params(), "order=tile,tile=8x8");
  try {
    make_generator({"noopt", "k=8"});
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("valid parameters: order, tile"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace raycoh
