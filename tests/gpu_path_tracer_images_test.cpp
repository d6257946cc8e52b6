// Whole images of the device path tracer (cuda/device_path_tracer.h) against the CPU path tracer's
// (shading/path_tracer.h) within their noise: the per-block z-test of shading/block_stats.h (8x8-pixel blocks,
// per-frame variance, no block and channel beyond |z| = 4) between the CPU renderer with seed 1 and the device one
// with seed 2 (independent estimates) at a fixed frame count; the same test must reject the CPU image made 10%
// brighter (50% at the simulator size). One test per scene of the coverage list (tests/path_tracer_coverage.h),
// which together cover every material class, textures, alpha masks and every light type; GpuPathTracerCoverage
// checks the list on the CPU. Label `gpu`; the image tests skip without a device, a scene whose file is absent is
// skipped by name, and a scene the list keeps off the simulator is skipped there with the list's reason.
// RAYCOH_GPU_TEST_SIZE=sim: 16x16 pixels, 16 frames, paths of 3 scattering events.
#include <gtest/gtest.h>

#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "cuda/cuda_device.h"
#include "cuda/device_path_tracer.h"
#include "generators/generator.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "shading/block_stats.h"
#include "shading/emitters.h"
#include "tests/block_stats_util.h"
#include "tests/gpu_path_tracer_util.h"
#include "tests/gpu_test_size.h"
#include "tests/path_tracer_coverage.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

using test::CoveredScene;

// The z-test of the device image (seed 2) against the CPU one (seed 1) and against the CPU one made brighter.
// require_power: also require that the CPU image made brighter is rejected (the test's power at this size).
void expect_images_agree(const Scene& scene, const std::string& name, bool require_power) {
  const int frames = test::gpu_test_size(128, 16);
  // 10% brighter must be rejected at the full size; the simulator's 4 blocks of 16 frames need a larger step.
  const float kBrighter = test::gpu_test_size(1.1f, 1.5f);
  const Bvh bvh = build_bvh(scene);
  const EmitterDistribution lights(scene);
  auto cpu = make_tracer({"cpu", ""}, scene, bvh);
  auto generator = make_generator({"noopt", ""});
  const RenderSettings cpu_rs = test::path_settings(1), gpu_rs = test::path_settings(2);
  // The CPU frames once, in two sets of statistics: as rendered, and brighter.
  PathTracer pt(scene, *cpu, *generator, cpu_rs);
  BlockFrameStats host(cpu_rs.width, cpu_rs.height), brighter(cpu_rs.width, cpu_rs.height);
  for (int f = 0; f < frames; ++f) {
    Accumulator acc(cpu_rs.width, cpu_rs.height);
    pt.render_frame(static_cast<uint32_t>(f), acc);
    std::vector<Vec3> samples = test::frame_samples(acc);
    host.add_frame(samples);
    for (Vec3& v : samples) v = v * kBrighter;
    brighter.add_frame(samples);
  }
  cuda::DevicePathTracer device(scene, bvh, lights.view(scene), *generator, test::device_settings(gpu_rs));
  BlockFrameStats gpu(gpu_rs.width, gpu_rs.height);
  std::vector<Vec3> radiance;
  uint64_t rays = 0;
  for (int f = 0; f < frames; ++f) {
    const cuda::DeviceFrameStats s = device.render_frame(static_cast<uint32_t>(f), radiance);
    rays += s.rays.primary + s.rays.secondary + s.rays.bounce + s.rays.shadow;
    EXPECT_EQ(s.rays.primary, static_cast<uint64_t>(gpu_rs.width) * gpu_rs.height);
    gpu.add_frame(radiance);
  }
  EXPECT_GT(rays, static_cast<uint64_t>(frames) * gpu_rs.width * gpu_rs.height);
  const BlockZTest same = block_z_test(gpu, host, 4.0);
  EXPECT_EQ(same.beyond, 0u) << same.summary();
  EXPECT_GT(same.max_abs_z, 0.0);
  EXPECT_EQ(gpu.non_finite(), 0u);
  const BlockZTest apart = block_z_test(gpu, brighter, 4.0);
  if (require_power) {
    EXPECT_GT(apart.beyond, 0u) << apart.summary();
  }
  std::printf("%s: device vs cpu %s; vs cpu x%.1f %s\n", name.c_str(), same.summary().c_str(), kBrighter,
              apart.summary().c_str());
}

// The image test of one scene of the coverage list, skipped when its file is absent or, at the simulator size,
// with the list's reason.
void expect_covered_scene_agrees(const std::string& name) {
  if (cuda::device_count() == 0) {
    GTEST_SKIP() << "no CUDA device";
  }
  const CoveredScene& c = test::covered(name);
  const bool sim = test::gpu_test_sim_size();
  if (sim && c.sim_skip) {
    GTEST_SKIP() << name << " at the simulator size: " << c.sim_skip;
  }
  std::string absent;
  const std::optional<Scene> scene = test::load_covered(c, absent);
  if (!scene) {
    GTEST_SKIP() << absent;
  }
  SCOPED_TRACE(name + " (" + test::feature_list(c.covers) + ")");
  expect_images_agree(*scene, name, !(sim ? c.sim_weak : c.full_weak));
}

TEST(GpuPathTracer, ImagesAgreeWithTheCpuWithinTheirNoiseOnCornell) { expect_covered_scene_agrees("cornell"); }

TEST(GpuPathTracer, ImagesAgreeWithTheCpuWithinTheirNoiseOnVoxels) { expect_covered_scene_agrees("voxels"); }

TEST(GpuPathTracer, ImagesAgreeWithTheCpuWithinTheirNoiseOnCornellWithPunctualLights) {
  expect_covered_scene_agrees("lit_cornell");
}

TEST(GpuPathTracer, ImagesAgreeWithTheCpuWithinTheirNoiseOnSibenikLamps) {
  expect_covered_scene_agrees("sibenik_lamps");
}

TEST(GpuPathTracer, ImagesAgreeWithTheCpuWithinTheirNoiseOnConferenceLamps) {
  expect_covered_scene_agrees("conference_lamps");
}

TEST(GpuPathTracer, ImagesAgreeWithTheCpuWithinTheirNoiseOnCountryKitchen) {
  expect_covered_scene_agrees("country_kitchen");
}

TEST(GpuPathTracer, ImagesAgreeWithTheCpuWithinTheirNoiseOnDamagedHelmet) {
  expect_covered_scene_agrees("DamagedHelmet");
}

TEST(GpuPathTracer, ImagesAgreeWithTheCpuWithinTheirNoiseOnAlphaBlendModeTest) {
  expect_covered_scene_agrees("AlphaBlendModeTest");
}

TEST(GpuPathTracer, ImagesAgreeWithTheCpuWithinTheirNoiseOnLightsPunctualLamp) {
  expect_covered_scene_agrees("LightsPunctualLamp");
}

// Every scene of the list has an image test above, and the list covers every feature; at the simulator size it
// says what the scenes rendered there leave to the GPU.
TEST(GpuPathTracerCoverage, TheListCoversEveryMaterialClassTextureMaskAndLightType) {
  const std::vector<std::string> tested = {
      "cornell",         "voxels",        "lit_cornell",        "sibenik_lamps",     "conference_lamps",
      "country_kitchen", "DamagedHelmet", "AlphaBlendModeTest", "LightsPunctualLamp"};
  uint32_t all = 0, sim = 0;
  ASSERT_EQ(test::coverage_list().size(), tested.size());
  for (size_t i = 0; i < tested.size(); ++i) {
    const CoveredScene& c = test::coverage_list()[i];
    EXPECT_EQ(tested[i], c.name);
    all |= c.covers;
    if (!c.sim_skip) sim |= c.covers;
  }
  EXPECT_EQ(all, test::kEveryFeature) << "missing: " << test::feature_list(test::kEveryFeature & ~all);
  std::printf("at the simulator size: %s; left to the GPU: %s\n", test::feature_list(sim).c_str(),
              test::feature_list(test::kEveryFeature & ~sim).c_str());
}

// The image tests' power, checked without a device: on every scene whose image test requires it at this size, the
// z-test rejects the CPU image with seed 1 made 10% brighter (50% at the simulator size) against the CPU image with
// seed 2, which is what the device image with seed 2 must see too.
TEST(GpuPathTracerCoverage, TheZTestRejectsABrighterImageOnTheCpuAlone) {
  const bool sim = test::gpu_test_sim_size();
  const int frames = test::gpu_test_size(128, 16);
  const float brighter = test::gpu_test_size(1.1f, 1.5f);
  for (const CoveredScene& c : test::coverage_list()) {
    std::string absent = (sim ? c.sim_skip || c.sim_weak : c.full_weak != nullptr) ? "not required at this size" : "";
    const std::optional<Scene> scene = absent.empty() ? test::load_covered(c, absent) : std::nullopt;
    if (!scene) {
      std::printf("%s: not checked (%s)\n", c.name, absent.c_str());
      continue;
    }
    SCOPED_TRACE(c.name);
    const Bvh bvh = build_bvh(*scene);
    auto cpu = make_tracer({"cpu", ""}, *scene, bvh);
    auto generator = make_generator({"noopt", ""});
    const BlockFrameStats a = test::cpu_block_stats(*scene, *cpu, *generator, test::path_settings(2), frames);
    const BlockFrameStats b = test::cpu_block_stats(*scene, *cpu, *generator, test::path_settings(1), frames, brighter);
    const BlockZTest apart = block_z_test(a, b, 4.0);
    EXPECT_GT(apart.beyond, 0u) << apart.summary();
    std::printf("%s: cpu vs cpu x%.1f %s\n", c.name, brighter, apart.summary().c_str());
  }
}

// Each scene that is present has what the list says, at the size its image test renders it (the full size where
// the list keeps it off the simulator).
TEST(GpuPathTracerCoverage, EachSceneHasWhatTheListSays) {
  for (const CoveredScene& c : test::coverage_list()) {
    SCOPED_TRACE(c.name);
    std::string absent;
    const std::optional<Scene> scene = test::load_covered(c, absent);
    if (!scene) {
      std::printf("%s: not checked (%s)\n", c.name, absent.c_str());
      continue;
    }
    const RenderSettings rs = test::path_settings(1, test::gpu_test_sim_size() && !c.sim_skip);
    const int w = rs.width, h = rs.height;
    const uint32_t has = test::features_of(*scene, w, h);
    EXPECT_EQ(c.covers & ~has, 0u) << "missing at " << w << "x" << h << ": " << test::feature_list(c.covers & ~has);
    std::printf("%s at %dx%d: %s\n", c.name, w, h, test::feature_list(has).c_str());
  }
}

}  // namespace
}  // namespace raycoh
