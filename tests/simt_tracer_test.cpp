// The `simt` tracer on real scenes: a warp of one lane equals closest_hit() with RayCounters; the tracer's hits
// equal the `cpu` tracer's bit for bit; counter identities; batches whose size is not a multiple of 32;
// determinism across thread counts; coherent orders beat scanline order. The warp model's steps on a hand-built
// BVH are tests/simt_warp_test.cpp.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "core/flush_denormals.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "simt/simt.h"
#include "tests/test_util.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

// ---- Real scenes ----

struct Batch {
  Scene scene;
  Bvh bvh;
  std::vector<Ray> rays;
};

// NoOpt diffuse/glossy secondary rays of frame 0, in the generator's order (tile-major unless `generator` says).
Batch make_batch(const std::string& scene_spec, int w, int h, const std::string& generator = "noopt") {
  Batch b{load_scene(scene_spec), {}, {}};
  b.bvh = build_bvh(b.scene);
  const auto order = make_pixel_order(w, h, RayOrder::Tile, 8, 8);
  const GBuffer gbuffer = first_hits(b.scene, *make_tracer({"cpu", ""}, b.scene, b.bvh), w, h, order, 1, 0).gbuffer;
  RayBatch batch;
  GenerationStats stats;
  make_generator(parse_plugin_spec(generator))->generate(b.scene, gbuffer, 1, batch, stats);
  b.rays = batch.rays;
  return b;
}

std::vector<std::string> real_scenes() {
  std::vector<std::string> specs = {"cornell", "voxels"};
  for (const auto& file : test::shared_scene_files())
    if (file.stem() == "sibenik" || file.stem() == "conference") specs.push_back(file.string());
  return specs;
}

class SimtOnScene : public ::testing::TestWithParam<std::string> {};

TEST_P(SimtOnScene, WarpOfOneIsClosestHitExactly) {
  const Batch b = make_batch(GetParam(), 64, 48);
  ASSERT_GT(b.rays.size(), 0u);
  const SimtConfig config = simt_config(b.bvh.view(), 1, 64, 32);
  CoherenceCounters total;
  total.warp_size = 1;
  for (size_t i = 0; i < b.rays.size(); ++i) {
    RayCounters expect_counters;
    const Hit expect = closest_hit(b.bvh.view(), b.rays[i], expect_counters);
    Hit hit;
    RayCounters counters;
    CoherenceCounters warp;
    simt_trace_warp(b.bvh.view(), &b.rays[i], 1, config, &hit, warp, nullptr, &counters);
    ASSERT_EQ(std::memcmp(&hit, &expect, sizeof(Hit)), 0) << "ray " << i;
    ASSERT_EQ(counters.nodes, expect_counters.nodes) << "ray " << i;
    ASSERT_EQ(counters.leaves, expect_counters.leaves) << "ray " << i;
    ASSERT_EQ(counters.triangles, expect_counters.triangles) << "ray " << i;
    // One lane: every step has one active lane, one line per node (64-byte lines) and one or two per triangle.
    ASSERT_EQ(warp.node_steps, counters.nodes);
    ASSERT_EQ(warp.node_lines, counters.nodes);
    ASSERT_EQ(warp.leaf_steps, counters.leaves);
    ASSERT_EQ(warp.triangle_steps, counters.triangles);
    total.add(warp);
  }
  EXPECT_DOUBLE_EQ(total.simt_efficiency(), 1.0);
}

void expect_identities(const CoherenceCounters& c, size_t rays) {
  EXPECT_EQ(c.rays, rays);
  EXPECT_EQ(c.warps, (rays + c.warp_size - 1) / c.warp_size);
  EXPECT_EQ(c.nodes, c.node_lanes);
  EXPECT_EQ(c.leaves, c.leaf_lanes);
  EXPECT_EQ(c.triangles, c.triangle_lanes);
  EXPECT_LE(c.node_lines, c.node_lanes);
  EXPECT_GE(c.node_lines, c.node_steps);
  EXPECT_LE(c.triangle_lines, 2 * c.triangle_lanes);
  EXPECT_GE(c.triangle_lines, c.triangle_steps);
  EXPECT_EQ(c.l1_hits + c.l1_misses, c.node_fetches + c.triangle_fetches);
  EXPECT_EQ(c.l2_hits + c.l2_misses, c.l1_misses);
  EXPECT_EQ(c.dram_bytes, c.l2_misses * c.sector_bytes);
  EXPECT_GT(c.simt_efficiency(), 0.0);
  EXPECT_LE(c.simt_efficiency(), 1.0);
  EXPECT_GT(c.modeled.ms, 0.0);
}

TEST_P(SimtOnScene, HitsEqualTheCpuTracerBitForBit) {
  const Batch b = make_batch(GetParam(), 96, 64);
  auto cpu = make_tracer({"cpu", ""}, b.scene, b.bvh);
  std::vector<Hit> expect(b.rays.size());
  cpu->trace(b.rays.data(), b.rays.size(), expect.data());
  for (const std::string params : {"", "warp=13,line=128,kernel=simple,block=96", "preset=h100,warp=64"}) {
    SCOPED_TRACE(params);
    auto simt = make_tracer({"simt", params}, b.scene, b.bvh);
    std::vector<Hit> hits(b.rays.size());
    simt->trace(b.rays.data(), b.rays.size(), hits.data());
    size_t differ = 0;
    for (size_t i = 0; i < hits.size(); ++i) differ += std::memcmp(&hits[i], &expect[i], sizeof(Hit)) != 0;
    EXPECT_EQ(differ, 0u) << "of " << hits.size() << " rays";
    ASSERT_NE(simt->last_counters(), nullptr);
    expect_identities(*simt->last_counters(), b.rays.size());
  }
}

// The two BVH2 kernels the model stands for count the same traversal (hits and warp counters equal) and differ in
// cost only: on incoherent rays the tuned kernel (16-byte loads, state in registers) needs fewer L1 wavefronts.
TEST_P(SimtOnScene, TunedAndClassicKernelsCountTheSameTraversal) {
  const Batch b = make_batch(GetParam(), 96, 64);
  CoherenceCounters c[2];
  std::vector<Hit> hits[2];
  const char* params[2] = {"preset=h100,traversal=classic", "preset=h100"};
  for (int k = 0; k < 2; ++k) {
    auto simt = make_tracer({"simt", params[k]}, b.scene, b.bvh);
    hits[k].resize(b.rays.size());
    simt->trace(b.rays.data(), b.rays.size(), hits[k].data());
    c[k] = *simt->last_counters();
  }
  EXPECT_EQ(std::memcmp(hits[0].data(), hits[1].data(), hits[0].size() * sizeof(Hit)), 0);
  EXPECT_EQ(c[0].node_steps, c[1].node_steps);
  EXPECT_EQ(c[0].node_lines, c[1].node_lines);
  EXPECT_EQ(c[0].triangle_fetches, c[1].triangle_fetches);
  EXPECT_LT(c[1].modeled.l1_wavefronts, c[0].modeled.l1_wavefronts);
  EXPECT_LT(c[1].modeled.l1_local_wavefronts, c[0].modeled.l1_local_wavefronts);
}

std::string scene_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string stem = std::filesystem::path(info.param).stem().string();
  for (char& c : stem)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return stem;
}

INSTANTIATE_TEST_SUITE_P(Scenes, SimtOnScene, ::testing::ValuesIn(real_scenes()), scene_name);

TEST(SimtTracer, BatchNotAMultipleOfTheWarpSize) {
  const Batch b = make_batch("cornell", 32, 24);
  const std::vector<Ray> rays(b.rays.begin(), b.rays.begin() + 45);
  auto simt = make_tracer({"simt", ""}, b.scene, b.bvh);
  std::vector<Hit> hits(rays.size());
  simt->trace(rays.data(), rays.size(), hits.data());
  const CoherenceCounters& c = *simt->last_counters();
  EXPECT_EQ(c.rays, 45u);
  EXPECT_EQ(c.warps, 2u);
  // The same as the two warps traced by hand: 32 lanes, then 13.
  const SimtConfig config = simt_config(b.bvh.view(), 32, 64, 32);
  CoherenceCounters expect;
  std::vector<Hit> expect_hits(45);
  {
    const FlushDenormalsScope ftz;
    simt_trace_warp(b.bvh.view(), rays.data(), 32, config, expect_hits.data(), expect);
    simt_trace_warp(b.bvh.view(), rays.data() + 32, 13, config, expect_hits.data() + 32, expect);
  }
  EXPECT_EQ(c.node_steps, expect.node_steps);
  EXPECT_EQ(c.node_lanes, expect.node_lanes);
  EXPECT_EQ(c.node_lines, expect.node_lines);
  EXPECT_EQ(c.triangle_lines, expect.triangle_lines);
  EXPECT_EQ(c.leaf_steps, expect.leaf_steps);
  EXPECT_EQ(std::memcmp(hits.data(), expect_hits.data(), 45 * sizeof(Hit)), 0);
  expect_identities(c, 45);
  EXPECT_DOUBLE_EQ(c.simt_efficiency(), expect.simt_efficiency());
  // The 19 missing lanes of the partial warp count as idle.
  CoherenceCounters partial;
  {
    const FlushDenormalsScope ftz;
    simt_trace_warp(b.bvh.view(), rays.data() + 32, 13, config, expect_hits.data() + 32, partial);
  }
  EXPECT_LE(partial.simt_efficiency(), 13.0 / 32.0);
  EXPECT_GT(partial.simt_efficiency(), 0.0);
  // Nothing to trace is no error.
  simt->trace(rays.data(), 0, hits.data());
  EXPECT_EQ(simt->last_counters()->rays, 0u);
  EXPECT_EQ(simt->last_counters()->simt_efficiency(), 0.0);
}

TEST(SimtTracer, IdenticalRaysShareEveryStep) {
  const Batch b = make_batch("voxels", 32, 24);
  const std::vector<Ray> rays(96, b.rays[b.rays.size() / 2]);
  auto simt =
      make_tracer({"simt", ""}, b.scene, b.bvh);  // persistent warps dealt in turn: warps 0, 1, 2 on SMs 0, 1, 2
  std::vector<Hit> hits(rays.size());
  simt->trace(rays.data(), rays.size(), hits.data());
  const CoherenceCounters& c = *simt->last_counters();
  EXPECT_DOUBLE_EQ(c.simt_efficiency(), 1.0);
  EXPECT_EQ(c.node_lines, c.node_steps);
  EXPECT_EQ(c.node_fetches, 2 * c.node_steps);
  // Three warps on SMs 0, 1, 2, in lock step: each L1 misses each distinct sector once (a repeat, e.g. two
  // triangles sharing a sector, hits), SM 0's miss goes to DRAM, SM 1's and SM 2's then hit in the L2.
  EXPECT_EQ(c.l1_misses, 3 * c.l2_misses);
  EXPECT_EQ(c.l2_hits, 2 * c.l2_misses);
  EXPECT_LE(c.l2_misses, (c.node_fetches + c.triangle_fetches) / 3);
}

TEST(SimtTracer, CountersAreTheSameForAnyThreadCount) {
  const Batch b = make_batch("voxels", 256, 192);  // more warps than one chunk of the tracer's pipeline
  auto simt = make_tracer({"simt", "sms=4,l1_kb=8,l2_mb=0.25"}, b.scene, b.bvh);
  auto run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    std::vector<Hit> hits(b.rays.size());
    simt->trace(b.rays.data(), b.rays.size(), hits.data());
    return std::make_pair(*simt->last_counters(), hits);
  };
  const auto [one, hits_one] = run(1);
  const auto [two, hits_two] = run(2);
  EXPECT_EQ(std::memcmp(hits_one.data(), hits_two.data(), hits_one.size() * sizeof(Hit)), 0);
  EXPECT_EQ(one.node_lines, two.node_lines);
  EXPECT_EQ(one.triangle_fetches, two.triangle_fetches);
  EXPECT_EQ(one.l1_hits, two.l1_hits);
  EXPECT_EQ(one.l2_hits, two.l2_hits);
  EXPECT_EQ(one.l2_misses, two.l2_misses);
  EXPECT_EQ(one.modeled.cycles, two.modeled.cycles);
  EXPECT_GT(one.l2_hits, 0u);
  EXPECT_GT(one.l2_misses, 0u);
}

TEST(SimtTracer, CoherentOrderBeatsScanlineOrder) {
  // The same rays, tile-major vs scanline (docs/design.md section 1): compact pixel blocks share more of each warp's
  // path, so they cannot be less efficient or touch more lines on a scene with locality.
  const Batch tile = make_batch("voxels", 128, 96, "noopt");
  const Batch scan = make_batch("voxels", 128, 96, "noopt:order=scanline");
  auto counters = [](const Batch& b) {
    auto simt = make_tracer({"simt", ""}, b.scene, b.bvh);
    std::vector<Hit> hits(b.rays.size());
    simt->trace(b.rays.data(), b.rays.size(), hits.data());
    return *simt->last_counters();
  };
  const CoherenceCounters t = counters(tile), s = counters(scan);
  ASSERT_EQ(t.rays, s.rays);
  EXPECT_GE(t.simt_efficiency(), s.simt_efficiency());
  EXPECT_LE(t.node_lines, s.node_lines);
}

TEST(SimtTracer, ParametersAndErrors) {
  const Batch b = make_batch("cornell", 8, 8);
  EXPECT_EQ(make_tracer({"simt", ""}, b.scene, b.bvh)->params(),
            "preset=rtx3060,kernel=persistent,block=128,warp=32,line=64,bvh=bvh2,traversal=tuned,regs=55,resident=0,"
            "sms=28,l1_kb=128,l2_mb=3,l1_tags=4,l1_banks=0,l1_words=0,dram_gbs=360,l2_bpc=1327.4073,node_cycles=98");
  EXPECT_EQ(make_tracer({"simt", "preset=h100,line=128,kernel=simple,block=256"}, b.scene, b.bvh)->params(),
            "preset=h100,kernel=simple,block=256,warp=32,line=128,bvh=bvh2,traversal=tuned,regs=54,resident=0,"
            "sms=132,l1_kb=256,l2_mb=50,l1_tags=4,l1_banks=0,l1_words=1,dram_gbs=3350,l2_bpc=3628.73,node_cycles=98");
  EXPECT_NE(make_tracer({"simt", "bvh=cwbvh"}, b.scene, b.bvh)->params().find("bvh=cwbvh,traversal=tuned,regs=66,"),
            std::string::npos);  // the CWBVH kernel's registers
  EXPECT_NE(make_tracer({"simt", "traversal=classic"}, b.scene, b.bvh)->params().find("regs=55,"),
            std::string::npos);  // the classic kernel's
  EXPECT_THROW(make_tracer({"simt", "bvh=cwbvh,traversal=classic"}, b.scene, b.bvh), Error);
  EXPECT_EQ(make_tracer({"cpu", ""}, b.scene, b.bvh)->last_counters(), nullptr);
  auto error_of = [&](const std::string& params) -> std::string {
    try {
      make_tracer({"simt", params}, b.scene, b.bvh);
    } catch (const Error& e) {
      return e.what();
    }
    return "(no error)";
  };
  EXPECT_NE(error_of("preset=rtx4090").find("rtx3060, h100"), std::string::npos);
  EXPECT_NE(error_of("warp=0").find("[1, 64]"), std::string::npos);
  EXPECT_NE(error_of("line=96").find("64, 128"), std::string::npos);
  EXPECT_NE(error_of("l2_mb=0.001").find("l2_mb"), std::string::npos);
  EXPECT_NE(error_of("cache=lru").find("unknown parameter 'cache'"), std::string::npos);
  EXPECT_NE(error_of("block=48").find("multiple of 32"), std::string::npos);
  EXPECT_NE(error_of("kernel=wide").find("persistent, simple"), std::string::npos);
  EXPECT_NE(error_of("regs=255,block=1024").find("does not fit"), std::string::npos);
}

}  // namespace
}  // namespace raycoh
