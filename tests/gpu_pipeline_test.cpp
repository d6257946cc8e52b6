// The device pipeline (cuda/device_pipeline.h: `cuda` with pipeline=device) against the host pipeline, ray for
// ray: camera rays, their hits and the G-buffer the device makes from them (whole, with its material table); then
// per generator and encoder the generated batch (every array and the statistics), the sort order, the physically
// permuted batch and the hits, each equal to what the CPU generator, encoders/reorder.h and the `cpu` tracer give.
// Counting pipelines count like `simt`. Small (48x32) so that it also runs under a GPU simulator. The refusal tests
// and the bad-parameter test run on the CPU; the others skip cleanly when cuda::device_count() == 0. Label `gpu`.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "bvh/bvh_build.h"
#include "cuda/cuda_device.h"
#include "cuda/device_pipeline.h"
#include "encoders/encoder.h"
#include "encoders/permute.h"
#include "encoders/reorder.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "generators/primary.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "records/provenance.h"
#include "scenes/scene.h"
#include "tests/batch_test_util.h"
#include "tests/gbuffer_test_util.h"
#include "tests/test_util.h"
#include "tests/trace_test_util.h"
#include "tracers/device_pipeline.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

using test::differing;

using test::differing_hits;
using test::trace_with;

#define SKIP_WITHOUT_GPU() \
  if (cuda::device_count() == 0) GTEST_SKIP() << "no CUDA device"

constexpr int kWidth = 48, kHeight = 32, kTile = 8;
constexpr uint32_t kSeed = 5, kFrame = 2;

// ShadingPoint has padding bytes (whatever a store left there): compare its fields, each bit for bit.
size_t differing_points(const std::vector<ShadingPoint>& a, const std::vector<ShadingPoint>& b) {
  if (a.size() != b.size()) return std::max(a.size(), b.size());
  const auto bits = [](const ShadingPoint& p) {
    return std::tuple(std::bit_cast<std::array<uint32_t, 12>>(std::array{p.position, p.ng, p.ns, p.wo}), p.prim,
                      p.material, p.cls, p.front_face);
  };
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i) n += bits(a[i]) != bits(b[i]);
  return n;
}

void expect_same_batch(const RayBatch& gpu, const RayBatch& cpu) {
  EXPECT_EQ(gpu.width, cpu.width);
  EXPECT_EQ(gpu.height, cpu.height);
  EXPECT_EQ(gpu.frame, cpu.frame);
  test::expect_same_columns(gpu, cpu);
}

void expect_same_stats(const GenerationStats& gpu, const GenerationStats& cpu) {
  EXPECT_EQ(gpu.rays, cpu.rays);
  EXPECT_EQ(gpu.below_geometric, cpu.below_geometric);
  EXPECT_EQ(gpu.below_shading, cpu.below_shading);
  EXPECT_EQ(gpu.non_finite, cpu.non_finite);
  for (int t = 0; t < 5; ++t) EXPECT_EQ(gpu.groups[t], cpu.groups[t]) << "groups of type " << t;
  EXPECT_EQ(gpu.hybrid_mean_fallback, cpu.hybrid_mean_fallback);
  EXPECT_EQ(gpu.reused_rays, cpu.reused_rays);
}

// A simulator's events may be coarse or zero (GPGPU-Sim without GPGPU_SIM_EVENT_CYCLES=1 reports whole seconds of
// wall clock): there only the relations between the times are checked.
bool simulated_device() {
  std::string name = cuda::device_name();
  for (char& ch : name) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return name.find("gpgpu") != std::string::npos;
}

// Stages a pass did not run are 0; every stage ran between the span's events, one after another on one stream.
void expect_stage_times(const DeviceStageTimes& t, bool keys, bool physical) {
  for (double ms : {t.gen_ms, t.key_ms, t.sort_ms, t.permute_ms, t.trace_ms, t.span_ms}) EXPECT_GE(ms, 0.0);
  if (!keys) {
    EXPECT_EQ(t.key_ms, 0.0);
    EXPECT_EQ(t.sort_ms, 0.0);
  }
  if (!physical) {
    EXPECT_EQ(t.permute_ms, 0.0);
  }
  EXPECT_GE(t.span_ms + 1e-3, t.stages_ms());  // events resolve about 0.5 us
  if (simulated_device()) return;
  EXPECT_GT(t.gen_ms, 0.0);
  EXPECT_GT(t.trace_ms, 0.0);
  if (keys) {
    EXPECT_GT(t.key_ms, 0.0);
    EXPECT_GT(t.sort_ms, 0.0);
  }
  if (physical) {
    EXPECT_GT(t.permute_ms, 0.0);
  }
}

// One scene on both sides: the cpu tracer and G-buffer, and a cuda tracer with its device pipeline.
struct Sides {
  Scene scene;
  Bvh bvh;
  std::unique_ptr<Tracer> cpu, cuda;
  DevicePipeline* pipeline = nullptr;
  FirstHits host;

  Sides(const std::string& spec, const std::string& cuda_params) : scene(load_scene(spec)), bvh(build_bvh(scene)) {
    cpu = make_tracer({"cpu", ""}, scene, bvh);
    cuda = make_tracer({"cuda", cuda_params}, scene, bvh);
    pipeline = cuda->device_pipeline();
    host = first_hits(scene, *cpu, kWidth, kHeight, make_pixel_order(kWidth, kHeight, RayOrder::Tile, kTile, kTile),
                      kSeed, kFrame, true);
  }

  void primary_pass() {
    expect_stage_times(pipeline->primary(kWidth, kHeight, kTile, kTile, kSeed, kFrame, true), false, false);
    pipeline->first_hits_gbuffer();
  }
};

TEST(GpuPipeline, CameraRaysHitsAndGBufferEqualTheCpu) {
  SKIP_WITHOUT_GPU();
  for (const char* spec : {"cornell", "voxels:size=16"}) {
    SCOPED_TRACE(spec);
    Sides s(spec, "");
    ASSERT_NE(s.pipeline, nullptr) << "pipeline=device is the default";
    s.pipeline->primary(kWidth, kHeight, kTile, kTile, kSeed, kFrame, true);
    PixelRays rays;
    std::vector<Hit> hits;
    s.pipeline->download_primary(rays, hits);
    EXPECT_EQ(differing(rays.rays, s.host.primary.rays), 0u);
    EXPECT_EQ(differing(rays.pixel, s.host.primary.pixel), 0u);
    EXPECT_EQ(differing_hits(hits, s.host.hits), 0u);
    s.pipeline->first_hits_gbuffer();
    const GBuffer g = s.pipeline->download_gbuffer();
    EXPECT_EQ(g.hits, s.host.gbuffer.hits);
    EXPECT_GT(g.hits, 0u);
    EXPECT_EQ(differing_points(g.points, s.host.gbuffer.points), 0u);
    const test::GBufferDiff diff = test::compare_gbuffers(g, s.host.gbuffer);  // the material table too
    EXPECT_EQ(diff.total(), 0u) << diff.summary();
  }
}

struct Case {
  std::string generator, encoder;
  PermuteMode mode;
};

std::vector<Case> pipeline_cases() {
  std::vector<Case> cases;
  for (const char* g : {"noopt", "ours", "contiguous"}) {
    cases.push_back({g, "none", PermuteMode::Physical});
    cases.push_back({g, "twopoint", PermuteMode::Physical});
    cases.push_back({g, "mlhcc", PermuteMode::Indirect});
  }
  for (const char* e : {"origin", "aila", "reis", "costa", "twopoint:bits=64"})
    cases.push_back({"noopt", e, PermuteMode::Physical});
  cases.push_back({"ours:tile=16x8,k=32", "origin", PermuteMode::Indirect});
  cases.push_back({"noopt:order=scanline", "aila", PermuteMode::Indirect});
  return cases;
}

// CUDA's atan2f / acosf may round a direction bit differently from glibc's (cuda/device_keys.h): these keys, and
// so their order, may differ on rare rays; every other key is equal bit for bit.
bool exact_keys(const std::string& encoder) { return encoder.rfind("reis", 0) != 0 && encoder.rfind("costa", 0) != 0; }

void expect_case_matches(Sides& s, const Case& c) {
  SCOPED_TRACE(c.generator + " + " + c.encoder + (c.mode == PermuteMode::Physical ? " physical" : " indirect"));
  auto generator = make_generator(parse_plugin_spec(c.generator));
  auto encoder = make_encoder(parse_plugin_spec(c.encoder), EncoderContext{s.scene.bounds, &s.bvh});
  ASSERT_EQ(s.pipeline->refusal(c.generator, *generator, *encoder), "");
  RayBatch batch, sorted;
  GenerationStats cpu_stats, gpu_stats;
  generator->generate(s.scene, s.host.gbuffer, kSeed, batch, cpu_stats);
  std::vector<uint32_t> order;
  ReorderTimings rt;
  const bool keys = reorder(*encoder, batch, c.mode, sorted, order, rt);
  const std::vector<Hit> unsorted_hits = trace_with(*s.cpu, batch.rays);

  const DeviceStageTimes t = s.pipeline->secondary(*generator, *encoder, c.mode, kSeed, gpu_stats);
  expect_stage_times(t, keys, keys && c.mode == PermuteMode::Physical);
  RayBatch generated, permuted;
  std::vector<uint32_t> gpu_order;
  std::vector<Hit> hits;
  s.pipeline->download_secondary(generated, gpu_order, permuted, hits);
  expect_same_batch(generated, batch);
  expect_same_stats(gpu_stats, cpu_stats);
  ASSERT_EQ(gpu_order.size(), order.size());
  if (keys) {
    ASSERT_TRUE(is_index_permutation(gpu_order, batch.size()));
  }
  if (exact_keys(c.encoder)) {
    EXPECT_EQ(gpu_order, order);
  }
  if (keys && c.mode == PermuteMode::Physical) {
    RayBatch expected;
    permute_batch(batch, gpu_order, expected);  // the gather of every array, by the device's own order
    expect_same_batch(permuted, expected);
    if (exact_keys(c.encoder)) expect_same_batch(permuted, sorted);
  } else {
    EXPECT_EQ(permuted.size(), 0u);
  }
  // hits[i] belongs to ray gpu_order[i] (or ray i without keys): the cpu tracer's hit of that ray, bit for bit.
  ASSERT_EQ(hits.size(), batch.size());
  std::vector<Hit> expected(hits.size());
  for (size_t i = 0; i < hits.size(); ++i) expected[i] = unsorted_hits[keys ? gpu_order[i] : i];
  EXPECT_EQ(differing_hits(hits, expected), 0u);
}

TEST(GpuPipeline, BatchesOrderAndHitsEqualTheHostPipeline) {
  SKIP_WITHOUT_GPU();
  for (const char* spec : {"cornell", "voxels:size=16"}) {
    SCOPED_TRACE(spec);
    Sides s(spec, "");
    s.primary_pass();
    for (const Case& c : pipeline_cases()) expect_case_matches(s, c);
  }
}

TEST(GpuPipeline, PersistentSimpleAndCwbvhKernelsTraceTheSameHits) {
  SKIP_WITHOUT_GPU();
  for (const char* params : {"kernel=simple,block=64", "bvh=cwbvh"}) {
    SCOPED_TRACE(params);
    Sides s("cornell", params);
    s.primary_pass();
    expect_case_matches(s, {"ours", "twopoint", PermuteMode::Physical});
    expect_case_matches(s, {"noopt", "origin", PermuteMode::Indirect});
  }
}

// counters=on: the counting kernel traces the device-made, device-sorted batch; its counters are simt's on the
// host-made, host-sorted one (the same rays in the same order).
TEST(GpuPipeline, CountingPipelineCountsLikeSimt) {
  SKIP_WITHOUT_GPU();
  Sides s("cornell", "counters=on");
  s.primary_pass();
  auto simt = make_tracer({"simt", ""}, s.scene, s.bvh);
  for (const char* e : {"none", "twopoint"}) {
    SCOPED_TRACE(e);
    auto generator = make_generator({"ours", ""});
    auto encoder = make_encoder(parse_plugin_spec(e), EncoderContext{s.scene.bounds, &s.bvh});
    RayBatch batch, sorted;
    GenerationStats stats;
    generator->generate(s.scene, s.host.gbuffer, kSeed, batch, stats);
    std::vector<uint32_t> order;
    ReorderTimings rt;
    const bool keys = reorder(*encoder, batch, PermuteMode::Physical, sorted, order, rt);
    trace_with(*simt, keys ? sorted.rays : batch.rays);
    s.pipeline->secondary(*generator, *encoder, PermuteMode::Physical, kSeed, stats);
    const CoherenceCounters* gpu = s.cuda->last_counters();
    const CoherenceCounters* model = simt->last_counters();
    ASSERT_NE(gpu, nullptr);
    ASSERT_NE(model, nullptr);
    EXPECT_EQ(gpu->rays, batch.size());
    const WarpStepCounters& g = *gpu;
    const WarpStepCounters& m = *model;
    EXPECT_EQ(std::memcmp(&g, &m, sizeof(WarpStepCounters)), 0)
        << "node steps " << g.node_steps << " / " << m.node_steps << ", lines " << g.node_lines << " / "
        << m.node_lines;
  }
}

// A table run end to end: the cuda rows are the device pipeline's, measured, beside cpu's rows of the same rays.
TEST(GpuPipeline, TableWritesMeasuredDeviceRows) {
  SKIP_WITHOUT_GPU();
  const std::filesystem::path out = test::temp_dir("gpu_pipeline_table") / "t.csv";
  const test::CommandResult r = test::run_raycoh(
      "table --scenes cornell --res 48x32 --frames 1 --repeat 1 --generators noopt,ours --encoders none,twopoint "
      "--tracers cpu,cuda,simt --out " +
      out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // A simulator build's device times are the simulator's: labelled SIMULATED, never MEASURED.
  const std::string word = simulated_device(PluginSpec{"cuda", ""}) ? "SIMULATED" : "MEASURED";
  EXPECT_NE(r.output.find(word + " on the GPU"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("vs modeled GPU, ms per frame"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(" " + word + " |"), std::string::npos) << r.output;  // the measured-vs-modeled column
  std::ifstream in(out);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find(",device,"), std::string::npos);
  EXPECT_NE(text.find("pipeline=device"), std::string::npos);
}

// ---- CPU: what the device pipeline refuses, and the parameter's choices ----

TEST(DevicePipelineRefusal, NamesWhatHasNoDeviceVersionAndWhatIsValid) {
  const Bounds box{Vec3{0, 0, 0}, Vec3{1, 1, 1}};
  auto none = make_encoder({"none", ""}, EncoderContext{box, nullptr});
  for (const char* g : {"direct"}) {
    const std::string why = cuda::device_pipeline_refusal(g, *make_generator({g, ""}), *none);
    EXPECT_NE(why.find(std::string("generator '") + g + "' has no device version"), std::string::npos) << why;
    EXPECT_NE(why.find("device generators: noopt, ours, contiguous, sadeghi, microjitter"), std::string::npos) << why;
    EXPECT_NE(why.find("pipeline=host"), std::string::npos) << why;
  }
  for (const char* g : {"sadeghi", "microjitter"})  // fused too (GpuSharedSample.TheDevicePipeline...)
    EXPECT_EQ(cuda::device_pipeline_refusal(g, *make_generator({g, ""}), *none, true), "") << g;
  const std::string scan =
      cuda::device_pipeline_refusal("ours", *make_generator({"ours", "order=scanline"}), *none, true);
  EXPECT_NE(scan.find("generator 'ours': order=scanline has no fused form"), std::string::npos) << scan;
  const std::string big = cuda::device_pipeline_refusal("ours", *make_generator({"ours", "tile=64x32,k=8"}), *none);
  EXPECT_NE(big.find("generator 'ours'"), std::string::npos) << big;
  EXPECT_NE(big.find("2048"), std::string::npos) << big;
  auto window = make_encoder({"window", ""}, EncoderContext{box, nullptr});
  const std::string w = cuda::device_pipeline_refusal("noopt", *make_generator({"noopt", ""}), *window);
  EXPECT_NE(w.find("encoder 'window' has no device version"), std::string::npos) << w;
  EXPECT_NE(w.find("device encoders: none, origin, reis, costa, aila, twopoint, mlhcc"), std::string::npos) << w;
  for (const char* g : {"noopt", "ours", "contiguous", "sadeghi", "microjitter"})
    for (const char* e : {"none", "origin", "reis", "costa", "aila", "twopoint"}) {
      auto encoder = make_encoder({e, ""}, EncoderContext{box, nullptr});
      EXPECT_EQ(cuda::device_pipeline_refusal(g, *make_generator({g, ""}), *encoder), "") << g << " + " << e;
    }
}

TEST(DevicePipelineRefusal, ABadPipelineValueIsAOneLineError) {
  const test::CommandResult r = test::run_raycoh("table --scenes cornell --res 16x16 --tracers cuda:pipeline=gpu");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("pipeline"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("device"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("host"), std::string::npos) << r.output;
}

TEST(DevicePipelineRefusal, TheTableRefusesADeviceRunOfAGeneratorWithoutADeviceVersion) {
  SKIP_WITHOUT_GPU();
  const test::CommandResult r =
      test::run_raycoh("table --scenes cornell --res 48x32 --frames 1 --generators direct --tracers cpu,cuda --out " +
                       (test::temp_dir("gpu_pipeline_refusal") / "t.csv").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("generator 'direct' has no device version"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace raycoh
