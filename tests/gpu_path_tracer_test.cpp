// The device path tracer (cuda/device_path_tracer.h) against the CPU path tracer (shading/path_tracer.h), bit for
// bit: for a fixed seed and frame the first bounce's batch (made by the device generator from the device camera
// pass) equals the CPU's in every column (test::expect_same_columns, tests/batch_test_util.h), and with the CPU's
// seed whole frames' radiance equals the CPU's on every scene of the coverage list (tests/path_tracer_coverage.h:
// every material class, textures, alpha masks, every light type) and BoxTextured, textured scenes included: sRGB
// texels are decoded by the same float operations on both sides (core/srgb_decode.h). Also the frame's per-stage
// GPU times. Whole images within their noise: tests/gpu_path_tracer_images_test.cpp. Label `gpu`; skips without a
// device, and skips absent scene files by name. RAYCOH_GPU_TEST_SIZE=sim: 16x16 pixels, paths of 3 scattering
// events.
#include <gtest/gtest.h>

#include <cctype>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "cuda/cuda_device.h"
#include "cuda/device_path_tracer.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "shading/emitters.h"
#include "tests/batch_test_util.h"
#include "tests/block_stats_util.h"
#include "tests/gpu_path_tracer_util.h"
#include "tests/gpu_test_size.h"
#include "tests/path_tracer_coverage.h"
#include "tests/test_util.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

#define SKIP_WITHOUT_GPU() \
  if (cuda::device_count() == 0) GTEST_SKIP() << "no CUDA device"

std::vector<std::string> test_scenes() {
  std::vector<std::string> scenes = {"cornell", "voxels:size=24"};
  for (const auto& path : test::shared_scene_files())
    if (path.filename() == "sibenik_lamps.glb") scenes.push_back(path.string());
  return scenes;
}

TEST(GpuPathTracer, FirstBounceRaysEqualTheCpuBitForBit) {
  SKIP_WITHOUT_GPU();
  constexpr uint32_t kFrame = 3;
  for (const std::string& spec : test_scenes()) {
    const Scene scene = load_scene(spec);
    const Bvh bvh = build_bvh(scene);
    const EmitterDistribution lights(scene);
    auto cpu = make_tracer({"cpu", ""}, scene, bvh);
    for (const char* gen : {"noopt", "ours"}) {
      SCOPED_TRACE(spec + " " + gen);
      const RenderSettings rs = test::path_settings(7);
      auto generator = make_generator({gen, ""});
      cuda::DevicePathTracer device(scene, bvh, lights.view(scene), *generator, test::device_settings(rs));
      std::vector<Vec3> radiance;
      device.render_frame(kFrame, radiance);
      RayBatch gpu, host;
      device.download_first_bounce(gpu);
      const auto order = make_pixel_order(rs.width, rs.height, RayOrder::Tile, 8, 8);
      const FirstHits first = first_hits(scene, *cpu, rs.width, rs.height, order, rs.seed, kFrame);
      GenerationStats stats;
      generator->generate(scene, first.gbuffer, rs.seed, host, stats);
      ASSERT_GT(host.size(), 0u);
      test::expect_same_columns(gpu, host);  // every column of RAYCOH_BATCH_COLUMNS, ours's group columns too
    }
  }
}

// A simulator's events keep the simulator's own clock (docs/gpgpusim.md): only the relations hold there.
bool simulated_device() {
  std::string name = cuda::device_name();
  for (char& ch : name) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return name.find("gpgpu") != std::string::npos;
}

// The frame's per-stage times tile its span: none negative, their sum at most frame_ms (events resolve about
// 0.5 us; every stage boundary adds one float rounding). On a GPU the camera, first-bounce generation, trace and
// gather stages take time; a simulator's event clock (docs/gpgpusim.md) is only held to the relations.
TEST(GpuPathTracer, StageTimesAreNonNegativeAndAddUpToAtMostTheFrame) {
  SKIP_WITHOUT_GPU();
  const Scene scene = load_scene("cornell");
  const Bvh bvh = build_bvh(scene);
  const EmitterDistribution lights(scene);
  auto generator = make_generator({"noopt", ""});
  cuda::DevicePathTracer device(scene, bvh, lights.view(scene), *generator,
                                test::device_settings(test::path_settings(3)));
  std::vector<Vec3> radiance;
  for (uint32_t f = 0; f < 2; ++f) {
    SCOPED_TRACE(f);
    const cuda::DeviceFrameStats s = device.render_frame(f, radiance);
    const cuda::DeviceFrameStages& t = s.stages;
    for (float ms : {t.camera_ms, t.generation_ms, t.next_event_ms, t.sample_ms, t.trace_ms, t.gather_ms})
      EXPECT_GE(ms, 0.f);
    EXPECT_GT(s.frame_ms, 0.f);
    EXPECT_LE(t.sum_ms(), s.frame_ms * (1.f + 1e-5f) + 0.01f);
    EXPECT_GT(t.sum_ms(), 0.f);
    std::printf(
        "frame %u: %.3f ms; camera %.3f, generation %.3f, next event %.3f, sample %.3f, trace %.3f, "
        "gather %.3f (sum %.3f)\n",
        f, s.frame_ms, t.camera_ms, t.generation_ms, t.next_event_ms, t.sample_ms, t.trace_ms, t.gather_ms, t.sum_ms());
    if (simulated_device()) continue;
    for (float ms : {t.camera_ms, t.generation_ms, t.trace_ms, t.gather_ms}) EXPECT_GT(ms, 0.f);
    EXPECT_GT(t.sum_ms(), 0.5f * s.frame_ms) << "the stages leave most of the frame uncounted";
  }
}

// With the same seed the device runs the CPU's estimator on the same random numbers, in the CPU's order of
// additions per pixel: every frame's radiance equals the CPU's bit for bit, on textured scenes too (their sRGB texels
// are decoded by core/srgb_decode.h's float operations on both sides). Scenes: the coverage list's (at the
// simulator size those it renders there) and BoxTextured.
TEST(GpuPathTracer, SameSeedFramesEqualTheCpuBitForBit) {
  SKIP_WITHOUT_GPU();
  std::vector<test::CoveredScene> scenes = test::coverage_list();
  scenes.push_back({"BoxTextured", "sample", "BoxTextured", test::kTextures});
  int compared = 0, textured = 0;
  for (const test::CoveredScene& c : scenes) {
    std::string absent = c.sim_skip && test::gpu_test_sim_size() ? "not at the simulator size" : "";
    const std::optional<Scene> scene = absent.empty() ? test::load_covered(c, absent) : std::nullopt;
    if (!scene) {
      std::printf("%s: not compared (%s)\n", c.name, absent.c_str());
      continue;
    }
    SCOPED_TRACE(c.name);
    const Bvh bvh = build_bvh(*scene);
    const EmitterDistribution lights(*scene);
    auto cpu = make_tracer({"cpu", ""}, *scene, bvh);
    auto generator = make_generator({"ours", ""});
    const RenderSettings rs = test::path_settings(9);
    PathTracer pt(*scene, *cpu, *generator, rs);
    cuda::DevicePathTracer device(*scene, bvh, lights.view(*scene), *generator, test::device_settings(rs));
    std::vector<Vec3> radiance;
    for (uint32_t f = 0; f < 2; ++f) {
      Accumulator acc(rs.width, rs.height);
      pt.render_frame(f, acc);
      device.render_frame(f, radiance);
      EXPECT_EQ(test::differing(radiance, test::frame_samples(acc)), 0u) << "frame " << f;
    }
    ++compared;
    textured += !scene->textures.empty();
    std::printf("%s%s: 2 frames compared\n", c.name, scene->textures.empty() ? "" : " (textured)");
  }
  EXPECT_GE(compared, 3) << "the built-in scenes are always there";
  if (textured == 0) std::printf("no textured scene present: the glTF samples are absent\n");
}

}  // namespace
}  // namespace raycoh
