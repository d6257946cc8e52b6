// The fused trace (`cuda:pipeline=fused`, cuda/fused_kernels.cu): one kernel makes each tile's secondary rays from
// the G-buffer and traces them where they are made. Its hits, at each ray's pixel, must be the `cpu` tracer's hits
// of the CPU generator's batch, bit for bit, for noopt, ours and contiguous in tile and group order, with every
// trace-kernel form (tuned, classic, CWBVH) and on a scene with alpha MASK cut-outs; its statistics must be the
// CPU generator's, and the batch the device generator makes again for download_secondary must be the CPU
// generator's in every column (test::expect_same_columns). Small (48x32) so that it also runs under a GPU simulator.
// What the fused pipeline refuses, and the parameter combinations it cannot run, are checked on the CPU. Label `gpu`.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "cuda/cuda_device.h"
#include "cuda/device_pipeline.h"
#include "encoders/encoder.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "tests/batch_test_util.h"
#include "tests/test_util.h"
#include "tests/trace_test_util.h"
#include "tracers/device_pipeline.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

namespace fs = std::filesystem;
using test::differing_hits;
using test::trace_with;

constexpr int kWidth = 48, kHeight = 32, kTile = 8;
constexpr uint32_t kSeed = 7, kFrame = 1;

#define SKIP_WITHOUT_GPU() \
  if (cuda::device_count() == 0) GTEST_SKIP() << "no CUDA device"

// The scenes: two built-in ones and, where the glTF samples are present, one with alpha MASK cut-outs.
std::vector<std::string> fused_scenes() {
  std::vector<std::string> specs = {"cornell", "voxels:size=16"};
  const fs::path masked = test::gltf_samples_dir() / "AlphaBlendModeTest" / "glTF-Binary" / "AlphaBlendModeTest.glb";
  if (fs::exists(masked)) specs.push_back(masked.string());
  return specs;
}

void expect_fused_hits_equal_cpu(const std::string& spec, const std::string& cuda_params,
                                 const std::vector<std::string>& generators) {
  SCOPED_TRACE(spec + " cuda:" + cuda_params);
  const Scene scene = load_scene(spec);
  const Bvh bvh = build_bvh(scene);
  auto cpu = make_tracer({"cpu", ""}, scene, bvh);
  auto cuda = make_tracer({"cuda", cuda_params}, scene, bvh);
  DevicePipeline* pipeline = cuda->device_pipeline();
  ASSERT_NE(pipeline, nullptr);
  pipeline->primary(kWidth, kHeight, kTile, kTile, kSeed, kFrame, true);
  pipeline->first_hits_gbuffer();
  const GBuffer g = pipeline->download_gbuffer();
  const FirstHits host =
      first_hits(scene, *cpu, kWidth, kHeight, make_pixel_order(kWidth, kHeight, RayOrder::Tile, kTile, kTile), kSeed,
                 kFrame, true);
  ASSERT_EQ(g.hits, host.gbuffer.hits);
  auto none = make_encoder({"none", ""}, EncoderContext{scene.bounds, &bvh});
  for (const std::string& name : generators) {
    SCOPED_TRACE(name);
    auto generator = make_generator(parse_plugin_spec(name));
    ASSERT_EQ(pipeline->refusal(name, *generator, *none), "");
    RayBatch batch;
    GenerationStats cpu_stats, gpu_stats;
    generator->generate(scene, host.gbuffer, kSeed, batch, cpu_stats);
    const std::vector<Hit> expected = trace_with(*cpu, batch.rays);
    const DeviceStageTimes t = pipeline->secondary(*generator, *none, PermuteMode::Physical, kSeed, gpu_stats);
    EXPECT_TRUE(t.fused);
    EXPECT_EQ(t.gen_ms, 0.0);  // the fused kernel's time is the trace's
    EXPECT_GE(t.trace_ms, 0.0);
    EXPECT_GE(t.span_ms + 1e-3, t.trace_ms);
    RayBatch generated, permuted;
    std::vector<uint32_t> order;
    std::vector<Hit> hits;
    pipeline->download_secondary(generated, order, permuted, hits);
    EXPECT_TRUE(order.empty());
    EXPECT_EQ(permuted.size(), 0u);
    ASSERT_EQ(generated.size(), batch.size());
    test::expect_same_columns(generated, batch);  // the device generator's batch, made again: every column
    EXPECT_EQ(differing_hits(hits, expected), 0u);
    EXPECT_EQ(gpu_stats.rays, cpu_stats.rays);
    EXPECT_EQ(gpu_stats.below_geometric, cpu_stats.below_geometric);
    EXPECT_EQ(gpu_stats.below_shading, cpu_stats.below_shading);
    EXPECT_EQ(gpu_stats.non_finite, cpu_stats.non_finite);
    for (int k = 0; k < 5; ++k) EXPECT_EQ(gpu_stats.groups[k], cpu_stats.groups[k]) << "groups of type " << k;
    EXPECT_EQ(gpu_stats.hybrid_mean_fallback, cpu_stats.hybrid_mean_fallback);
    EXPECT_EQ(gpu_stats.reused_rays, cpu_stats.reused_rays);
  }
}

TEST(GpuFused, HitsEqualTheCpuTracerForEveryGeneratorAndOrder) {
  SKIP_WITHOUT_GPU();
  const std::vector<std::string> generators = {"noopt",
                                               "noopt:order=scanline",
                                               "ours",
                                               "ours:order=group",
                                               "ours:tile=16x8,k=5,order=group,hybrid=glossy",
                                               "ours:tile=16x16,k=64",
                                               "contiguous",
                                               "contiguous:tile=3x5,k=4,order=group"};
  for (const std::string& spec : fused_scenes()) expect_fused_hits_equal_cpu(spec, "pipeline=fused", generators);
}

TEST(GpuFused, EveryKernelFormTracesTheSameHits) {
  SKIP_WITHOUT_GPU();
  for (const char* params : {"pipeline=fused,traversal=classic", "pipeline=fused,bvh=cwbvh"})
    expect_fused_hits_equal_cpu("cornell", params, {"noopt", "ours:order=group", "contiguous"});
}

// ---- CPU: what the fused pipeline refuses, and what it cannot be combined with ----

TEST(FusedRefusal, EncodersWithKeysAndScanlineGroupingAreRefusedInOneLine) {
  const Bounds box{Vec3{0, 0, 0}, Vec3{1, 1, 1}};
  auto none = make_encoder({"none", ""}, EncoderContext{box, nullptr});
  auto twopoint = make_encoder({"twopoint", ""}, EncoderContext{box, nullptr});
  for (const char* g : {"noopt", "ours", "contiguous", "ours:order=group", "noopt:order=scanline"})
    EXPECT_EQ(cuda::device_pipeline_refusal(g, *make_generator(parse_plugin_spec(g)), *none, true), "") << g;
  const std::string keys = cuda::device_pipeline_refusal("ours", *make_generator({"ours", ""}), *twopoint, true);
  EXPECT_NE(keys.find("encoder 'twopoint'"), std::string::npos) << keys;
  EXPECT_NE(keys.find("pipeline=fused"), std::string::npos) << keys;
  EXPECT_EQ(keys.find('\n'), std::string::npos) << keys;
  EXPECT_EQ(cuda::device_pipeline_refusal("ours", *make_generator({"ours", ""}), *twopoint, false), "");
  const std::string scan =
      cuda::device_pipeline_refusal("ours", *make_generator({"ours", "order=scanline"}), *none, true);
  EXPECT_NE(scan.find("order=scanline has no fused form"), std::string::npos) << scan;
  const std::string direct = cuda::device_pipeline_refusal("direct", *make_generator({"direct", ""}), *none, true);
  EXPECT_NE(direct.find("has no device version"), std::string::npos) << direct;
}

TEST(FusedRefusal, CountersAndASharedStackCannotBeFused) {
  const Scene scene = load_scene("cornell");
  const Bvh bvh = build_bvh(scene);
  for (const auto& [params, words] : std::vector<std::pair<std::string, std::string>>{
           {"pipeline=fused,counters=on", "counters=on"}, {"pipeline=fused,bvh=cwbvh,stack=shared", "stack=shared"}}) {
    try {
      make_tracer({"cuda", params}, scene, bvh);
      ADD_FAILURE() << params << " was accepted";
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(words), std::string::npos) << what;
      EXPECT_NE(what.find("pipeline=fused"), std::string::npos) << what;
    }
  }
}

}  // namespace
}  // namespace raycoh
