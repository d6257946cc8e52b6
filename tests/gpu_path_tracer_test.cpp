// The device path tracer (cuda/device_path_tracer.h) against the CPU path tracer (shading/path_tracer.h): for a
// fixed seed and frame the first bounce's rays (made by the device generator from the device camera pass) equal
// the CPU's bit for bit, and whole images agree within their noise: the per-block z-test of shading/block_stats.h
// (8x8-pixel blocks, per-frame variance, no block and channel beyond |z| = 4) between the CPU renderer with seed 1
// and the device one with seed 2 (independent estimates), on built-in scenes and sibenik_lamps when the shared
// scenes are present; the same test must reject the CPU image made 10% brighter (50% at the simulator size). Label
// `gpu`; skips without a device. glTF samples with textures, alpha masks and punctual lights are tested too when
// they are there. RAYCOH_GPU_TEST_SIZE=sim: 16x16 pixels, 16 frames, paths of 3 scattering events.
#include <gtest/gtest.h>

#include <cctype>
#include <cstdio>
#include <cstring>
#include <filesystem>
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
#include "shading/block_stats.h"
#include "shading/emitters.h"
#include "tests/block_stats_util.h"
#include "tests/gpu_test_size.h"
#include "tests/test_util.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

#define SKIP_WITHOUT_GPU() \
  if (cuda::device_count() == 0) GTEST_SKIP() << "no CUDA device"

RenderSettings settings(uint32_t seed) {
  RenderSettings rs;
  rs.width = test::gpu_test_size(64, 16);
  rs.height = test::gpu_test_size(48, 16);
  rs.seed = seed;
  rs.max_depth = test::gpu_test_size(5, 3);
  rs.rr_depth = test::gpu_test_size(3, 2);
  return rs;
}

cuda::DevicePathSettings device_settings(const RenderSettings& rs) {
  return {rs.width, rs.height, rs.seed, rs.max_depth, rs.rr_depth};
}

std::vector<std::string> test_scenes() {
  std::vector<std::string> scenes = {"cornell", "voxels:size=24"};
  for (const auto& path : test::shared_scene_files())
    if (path.filename() == "sibenik_lamps.glb") scenes.push_back(path.string());
  return scenes;
}

template <class T>
size_t differing(const std::vector<T>& a, const std::vector<T>& b) {
  if (a.size() != b.size()) return std::max(a.size(), b.size());
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i) n += std::memcmp(&a[i], &b[i], sizeof(T)) != 0;
  return n;
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
      const RenderSettings rs = settings(7);
      auto generator = make_generator({gen, ""});
      cuda::DevicePathTracer device(scene, bvh, lights.view(scene), *generator, device_settings(rs));
      std::vector<Vec3> radiance;
      device.render_frame(kFrame, radiance);
      RayBatch gpu, host;
      device.download_first_bounce(gpu);
      const auto order = make_pixel_order(rs.width, rs.height, RayOrder::Tile, 8, 8);
      const FirstHits first = first_hits(scene, *cpu, rs.width, rs.height, order, rs.seed, kFrame);
      GenerationStats stats;
      generator->generate(scene, first.gbuffer, rs.seed, host, stats);
      ASSERT_GT(host.size(), 0u);
      ASSERT_EQ(gpu.size(), host.size());
      EXPECT_EQ(differing(gpu.rays, host.rays), 0u);
      EXPECT_EQ(differing(gpu.pixel, host.pixel), 0u);
      EXPECT_EQ(differing(gpu.pdf, host.pdf), 0u);
      EXPECT_EQ(differing(gpu.weight, host.weight), 0u);
      EXPECT_EQ(differing(gpu.material, host.material), 0u);
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
  cuda::DevicePathTracer device(scene, bvh, lights.view(scene), *generator, device_settings(settings(3)));
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
// additions per pixel: on scenes without textures (whose sRGB decoding calls powf, which CUDA and glibc round
// differently) every frame's radiance equals the CPU's bit for bit.
TEST(GpuPathTracer, SameSeedFramesEqualTheCpuBitForBitWithoutTextures) {
  SKIP_WITHOUT_GPU();
  for (const std::string& spec : test_scenes()) {
    SCOPED_TRACE(spec);
    const Scene scene = load_scene(spec);
    ASSERT_TRUE(scene.textures.empty());
    const Bvh bvh = build_bvh(scene);
    const EmitterDistribution lights(scene);
    auto cpu = make_tracer({"cpu", ""}, scene, bvh);
    auto generator = make_generator({"ours", ""});
    const RenderSettings rs = settings(9);
    PathTracer pt(scene, *cpu, *generator, rs);
    cuda::DevicePathTracer device(scene, bvh, lights.view(scene), *generator, device_settings(rs));
    std::vector<Vec3> radiance;
    for (uint32_t f = 0; f < 2; ++f) {
      Accumulator acc(rs.width, rs.height);
      pt.render_frame(f, acc);
      device.render_frame(f, radiance);
      EXPECT_EQ(differing(radiance, test::frame_samples(acc)), 0u) << "frame " << f;
    }
  }
}

// The z-test of the device image (seed 2) against the CPU one (seed 1) and against the CPU one made brighter.
// require_power: also require that the CPU image made brighter is rejected (the test's power at this size).
void expect_images_agree(const std::string& spec, bool require_power = true) {
  const int frames = test::gpu_test_size(128, 16);
  // 10% brighter must be rejected at the full size; the simulator's 4 blocks of 16 frames need a larger step.
  const float kBrighter = test::gpu_test_size(1.1f, 1.5f);
  SCOPED_TRACE(spec);
  const Scene scene = load_scene(spec);
  const Bvh bvh = build_bvh(scene);
  const EmitterDistribution lights(scene);
  auto cpu = make_tracer({"cpu", ""}, scene, bvh);
  auto generator = make_generator({"noopt", ""});
  const RenderSettings cpu_rs = settings(1), gpu_rs = settings(2);
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
  cuda::DevicePathTracer device(scene, bvh, lights.view(scene), *generator, device_settings(gpu_rs));
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
  if (require_power) EXPECT_GT(apart.beyond, 0u) << apart.summary();
  std::printf("%s: device vs cpu %s; vs cpu x%.1f %s\n", spec.c_str(), same.summary().c_str(), kBrighter,
              apart.summary().c_str());
}

TEST(GpuPathTracer, ImagesAgreeWithTheCpuWithinTheirNoiseOnCornell) {
  SKIP_WITHOUT_GPU();
  expect_images_agree("cornell");
}

TEST(GpuPathTracer, ImagesAgreeWithTheCpuWithinTheirNoiseOnVoxels) {
  SKIP_WITHOUT_GPU();
  expect_images_agree("voxels:size=24");
}

TEST(GpuPathTracer, ImagesAgreeWithTheCpuWithinTheirNoiseOnSibenikLamps) {
  SKIP_WITHOUT_GPU();
  const std::vector<std::string> scenes = test_scenes();
  if (scenes.size() < 3) GTEST_SKIP() << "no shared scene sibenik_lamps";
  expect_images_agree(scenes[2]);
}

// Textures (base colour, metallic-roughness, emissive and normal maps: DamagedHelmet), alpha MASK cut-outs traced
// by the device kernel's any-hit test (AlphaBlendModeTest) and punctual lights (LightsPunctualLamp), from the glTF
// samples beside the shared scenes when they are there.
TEST(GpuPathTracer, ImagesAgreeWithTheCpuWithinTheirNoiseOnTexturedMaskedAndPunctualSamples) {
  SKIP_WITHOUT_GPU();
  const std::filesystem::path dir = test::gltf_samples_dir();
  const std::vector<std::filesystem::path> samples = {
      dir / "DamagedHelmet" / "glTF-Binary" / "DamagedHelmet.glb",
      dir / "AlphaBlendModeTest" / "glTF-Binary" / "AlphaBlendModeTest.glb",
      dir / "LightsPunctualLamp" / "glTF" / "LightsPunctualLamp.gltf"};
  int found = 0;
  for (const auto& path : samples) {
    if (dir.empty() || !std::filesystem::exists(path)) continue;
    ++found;
    // LightsPunctualLamp at the simulator's 16 frames of 16x16 is too noisy to reject a 1.5x brighter image (max
    // |z| 2.46 under GPGPU-Sim, 2026-11-29): its agreement is checked there, its power only at the full size.
    const bool lamp = path.filename() == "LightsPunctualLamp.gltf";
    expect_images_agree(path.string(), !(lamp && test::gpu_test_sim_size()));
  }
  if (found == 0) GTEST_SKIP() << "no glTF samples";
}

}  // namespace
}  // namespace raycoh
