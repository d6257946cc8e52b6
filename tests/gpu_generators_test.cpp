// The per-frame pipeline on the GPU (cuda/device_generators.h) against the CPU, byte for byte: sincos_turns on
// every rng_float value, primary rays in tile and scanline order, and the noopt / ours / contiguous / sadeghi /
// microjitter batches (every array and the statistics) on cornell, voxels and sibenik, with stiff G-buffer entries
// mixed in. The sincos accuracy test and the configuration checks run on the CPU alone; the others skip cleanly
// when cuda::device_count() == 0. Label `gpu`.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "core/sampling.h"
#include "cuda/cuda_device.h"
#include "cuda/device_generators.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "generators/primary.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "tests/batch_test_util.h"
#include "tests/gpu_test_size.h"
#include "tests/test_util.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

using test::differing;

#define SKIP_WITHOUT_GPU() \
  if (cuda::device_count() == 0) GTEST_SKIP() << "no CUDA device"

// Every value rng_float can return: k / 2^24. At the simulator size every 251st (a prime: all residues of the
// quadrant and table steps are met) and the last 256.
std::vector<float> all_rng_floats() {
  const uint32_t stride = test::gpu_test_size(1u, 251u);
  std::vector<float> u;
  for (uint32_t k = 0; k < (1u << 24); ++k)
    if (k % stride == 0 || k >= (1u << 24) - 256) u.push_back(static_cast<float>(k) * (1.f / 16777216.f));
  return u;
}

// ---- sincos_turns (CPU) ----

TEST(SincosTurns, PolynomialIsAccurateOnEveryRngValue) {
  double max_sin = 0, max_cos = 0, max_norm = 0;
  for (uint32_t k = 0; k < (1u << 24); ++k) {
    const float u = static_cast<float>(k) * (1.f / 16777216.f);
    float s, c;
    sincos_turns(u, s, c);
    const double phi = 2.0 * std::numbers::pi * static_cast<double>(u);
    max_sin = std::max(max_sin, std::abs(s - std::sin(phi)));
    max_cos = std::max(max_cos, std::abs(c - std::cos(phi)));
    max_norm = std::max(max_norm, std::abs(double(s) * s + double(c) * c - 1.0));
  }
  // The documented bounds (core/sampling.h): 9.6e-8 and 2.1e-7.
  EXPECT_LT(max_sin, 1e-7);
  EXPECT_LT(max_cos, 1e-7);
  EXPECT_LT(max_norm, 2.2e-7);
  float s, c;
  sincos_turns(0.f, s, c);
  EXPECT_EQ(s, 0.f);
  EXPECT_EQ(c, 1.f);
  sincos_turns(0.25f, s, c);
  EXPECT_EQ(s, 1.f);
  EXPECT_EQ(c, 0.f);
  sincos_turns(0.5f, s, c);
  EXPECT_EQ(s, 0.f);
  EXPECT_EQ(c, -1.f);
  sincos_turns(0.75f, s, c);
  EXPECT_EQ(s, -1.f);
  EXPECT_EQ(c, 0.f);
  // Half a turn apart, the quadrant reduction gives exactly opposite values (u = k / 2^24 < 1/2: u + 1/2 is exact).
  for (uint32_t k : {1u, 12345u, 1677721u, 3355443u, 5033165u, 8388607u}) {
    const float u = static_cast<float>(k) * (1.f / 16777216.f);
    float s1, c1, s2, c2;
    sincos_turns(u, s1, c1);
    sincos_turns(u + 0.5f, s2, c2);
    EXPECT_EQ(s1, -s2) << u;
    EXPECT_EQ(c1, -c2) << u;
  }
}

TEST(SincosTurns, DeviceEqualsHostBitForBit) {
  SKIP_WITHOUT_GPU();
  std::vector<float> u = all_rng_floats();
  for (float extra : {0.99999994f, 0.125f, 0.375f, 0.625f, 0.875f, -0.25f, 1.5f, 3.7f}) u.push_back(extra);
  std::vector<float> s(u.size()), c(u.size());
  cuda::sincos_turns_gpu(u.data(), u.size(), s.data(), c.data());
  size_t differ = 0;
  for (size_t i = 0; i < u.size(); ++i) {
    float hs, hc;
    sincos_turns(u[i], hs, hc);
    if (std::memcmp(&hs, &s[i], 4) != 0 || std::memcmp(&hc, &c[i], 4) != 0) {
      if (++differ <= 3)
        ADD_FAILURE() << "u = " << u[i] << ": host " << hs << ", " << hc << " device " << s[i] << ", " << c[i];
    }
  }
  EXPECT_EQ(differ, 0u);
}

// ---- primary rays ----

TEST(GpuPrimary, RaysEqualTheCpuForEveryOrderAndSize) {
  SKIP_WITHOUT_GPU();
  const Scene scene = load_scene("cornell");
  struct Case {
    int width, height;
    RayOrder order;
    int tile_w, tile_h;
    bool jitter;
  };
  const int w = test::gpu_test_size(256, 64), h = test::gpu_test_size(192, 48);  // simulator: 64x48
  for (const Case& c : std::vector<Case>{{w, h, RayOrder::Tile, 8, 8, true},
                                         {w, h, RayOrder::Tile, 8, 8, false},
                                         {w - 6, h - 2, RayOrder::Tile, 16, 8, true},  // partial tiles at the borders
                                         {13, 9, RayOrder::Tile, 4, 4, true},
                                         {1, 1, RayOrder::Tile, 8, 8, true},
                                         {7, 5, RayOrder::Tile, 32, 32, true},  // a tile larger than the image
                                         {w * 5 / 2, h * 5 / 2, RayOrder::Scanline, 8, 8, true}}) {
    SCOPED_TRACE(std::to_string(c.width) + "x" + std::to_string(c.height) + " tile " + std::to_string(c.tile_w) + "x" +
                 std::to_string(c.tile_h) + (c.order == RayOrder::Tile ? " tile order" : " scanline"));
    const PixelRays cpu =
        make_primary_rays(scene.camera, c.width, c.height,
                          make_pixel_order(c.width, c.height, c.order, c.tile_w, c.tile_h), 3, 2, c.jitter);
    PixelRays gpu;
    float ms = -1.f;
    cuda::make_primary_rays_gpu(scene.camera, c.width, c.height, c.order, c.tile_w, c.tile_h, 3, 2, c.jitter, gpu, &ms);
    EXPECT_GE(ms, 0.f);
    ASSERT_EQ(gpu.rays.size(), cpu.rays.size());
    EXPECT_EQ(gpu.pixel, cpu.pixel);
    EXPECT_EQ(std::memcmp(gpu.rays.data(), cpu.rays.data(), cpu.rays.size() * sizeof(Ray)), 0);
    EXPECT_EQ(gpu.width, cpu.width);
    EXPECT_EQ(gpu.height, cpu.height);
    EXPECT_EQ(gpu.frame, cpu.frame);
  }
}

// ---- generators ----

void expect_same_batch(const RayBatch& gpu, const RayBatch& cpu, const GenerationStats& gs, const GenerationStats& cs) {
  EXPECT_EQ(gpu.width, cpu.width);
  EXPECT_EQ(gpu.height, cpu.height);
  EXPECT_EQ(gpu.frame, cpu.frame);
  ASSERT_EQ(gpu.size(), cpu.size());
  test::expect_same_columns(gpu, cpu);
  for (size_t i = 0; i < cpu.size(); ++i)
    if (std::memcmp(&gpu.rays[i], &cpu.rays[i], sizeof(Ray)) != 0) {
      ADD_FAILURE() << "first differing ray " << i << " (pixel " << cpu.pixel[i] << "): gpu dir " << gpu.rays[i].dir.x
                    << " " << gpu.rays[i].dir.y << " " << gpu.rays[i].dir.z << ", cpu dir " << cpu.rays[i].dir.x << " "
                    << cpu.rays[i].dir.y << " " << cpu.rays[i].dir.z;
      break;
    }
  EXPECT_EQ(gs.rays, cs.rays);
  EXPECT_EQ(gs.below_geometric, cs.below_geometric);
  EXPECT_EQ(gs.below_shading, cs.below_shading);
  EXPECT_EQ(gs.non_finite, cs.non_finite);
  for (int t = 0; t < 5; ++t) EXPECT_EQ(gs.groups[t], cs.groups[t]) << "groups of type " << t;
  EXPECT_EQ(gs.hybrid_mean_fallback, cs.hybrid_mean_fallback);
  EXPECT_EQ(gs.reused_rays, cs.reused_rays);
}

GBuffer frame_gbuffer(const Scene& scene, const Bvh& bvh, int width, int height, uint32_t frame, bool stiff) {
  GBuffer g = first_hits(scene, *make_tracer({"cpu", ""}, scene, bvh), width, height,
                         make_pixel_order(width, height, RayOrder::Tile, 8, 8), 1, frame)
                  .gbuffer;
  if (stiff) {  // non-finite positions and normals, normals at the ONB's pole
    size_t seen = 0;
    for (ShadingPoint& sp : g.points) {
      if (!sp.valid()) continue;
      ++seen;
      if (seen % 211 == 0) sp.position.x = std::nanf("");
      if (seen % 223 == 0) sp.ns = Vec3{std::nanf(""), 0.f, 1.f};
      if (seen % 227 == 0) sp.ns = sp.ng = Vec3{0.f, 0.f, -1.f};
    }
  }
  return g;
}

void expect_gpu_generator_matches(const Scene& scene, const GBuffer& g, const std::string& spec_text,
                                  cuda::DeviceGenerator& device) {
  SCOPED_TRACE(spec_text);
  const PluginSpec spec = parse_plugin_spec(spec_text);
  auto cpu = make_generator(spec);
  RayBatch cpu_batch, gpu_batch;
  GenerationStats cpu_stats, gpu_stats;
  cpu->generate(scene, g, 7, cpu_batch, cpu_stats);
  device.generate(g, 7, *cpu, gpu_batch, gpu_stats);
  EXPECT_GE(device.last_kernel_ms(), 0.f);
  expect_same_batch(gpu_batch, cpu_batch, gpu_stats, cpu_stats);
}

const std::vector<std::string>& generator_specs() {
  static const std::vector<std::string> specs = {"noopt",
                                                 "noopt:order=scanline",
                                                 "noopt:tile=16x8",
                                                 "noopt:tile=64x64",
                                                 "ours",
                                                 "ours:k=1",
                                                 "ours:k=64",
                                                 "ours:k=5",
                                                 "ours:tile=16x8,k=32",
                                                 "ours:tile=32x32,k=16",
                                                 "ours:tile=32x32,k=1",
                                                 "ours:order=group",
                                                 "ours:order=scanline",
                                                 "ours:seed=99",
                                                 "ours:tile=3x5,k=4",
                                                 "ours:hybrid=donor",
                                                 "ours:hybrid=glossy,frame=rotate",
                                                 "ours:hybrid=independent,k=16",
                                                 "ours:frame=rotate",
                                                 "contiguous",
                                                 "contiguous:k=4,order=group"};
  return specs;
}

TEST(GpuGenerators, BatchesEqualTheCpuByteForByte) {
  SKIP_WITHOUT_GPU();
  std::vector<std::string> scenes = {"cornell", "voxels:size=48"};
  for (const auto& path : test::shared_scene_files())
    if (path.filename() == "sibenik.glb") scenes.push_back(path.string());
  // Materials per texel at the hit (the G-buffer's own material table goes up with its points).
  const std::filesystem::path helmet = test::gltf_samples_dir() / "DamagedHelmet" / "glTF-Binary" / "DamagedHelmet.glb";
  if (std::filesystem::exists(helmet)) scenes.push_back(helmet.string());
  for (const std::string& name : scenes) {
    SCOPED_TRACE(name);
    const Scene scene = load_scene(name);
    const Bvh bvh = build_bvh(scene);
    cuda::DeviceGenerator device(scene);
    for (bool stiff : {false, true}) {
      SCOPED_TRACE(stiff ? "stiff G-buffer" : "G-buffer");
      // Partial tiles at the borders for every tile size; simulator size 70x38.
      const GBuffer g =
          frame_gbuffer(scene, bvh, test::gpu_test_size(250, 70), test::gpu_test_size(190, 38), stiff ? 3u : 0u, stiff);
      for (const std::string& spec : generator_specs()) expect_gpu_generator_matches(scene, g, spec, device);
    }
  }
}

// sadeghi (interleave 1 and 4, N^2 >= pixels: no reuse) and microjitter (two radii), tile and scanline order: the
// per-pixel kernel with the shared numbers rule (generators/shared_sample.h), reused rays counted as on the CPU.
TEST(GpuGenerators, SharedSampleBatchesEqualTheCpuByteForByte) {
  SKIP_WITHOUT_GPU();
  for (const char* name : {"cornell", "voxels:size=48"}) {
    SCOPED_TRACE(name);
    const Scene scene = load_scene(name);
    const Bvh bvh = build_bvh(scene);
    cuda::DeviceGenerator device(scene);
    for (bool stiff : {false, true}) {
      SCOPED_TRACE(stiff ? "stiff G-buffer" : "G-buffer");
      const GBuffer g =
          frame_gbuffer(scene, bvh, test::gpu_test_size(250, 70), test::gpu_test_size(190, 38), stiff ? 3u : 1u, stiff);
      for (const char* spec : {"sadeghi", "sadeghi:interleave=4", "sadeghi:interleave=4,order=scanline,tile=16x4",
                               "sadeghi:interleave=300", "microjitter", "microjitter:radius=0.5,tile=32x16"})
        expect_gpu_generator_matches(scene, g, spec, device);
    }
  }
}

// Images smaller than a tile, 1x1, K = W H, K not dividing W H, and an image with no hit at all.
TEST(GpuGenerators, EdgeCasesEqualTheCpu) {
  SKIP_WITHOUT_GPU();
  const Scene scene = load_scene("cornell");
  const Bvh bvh = build_bvh(scene);
  cuda::DeviceGenerator device(scene);
  for (auto [w, h] : std::vector<std::pair<int, int>>{{1, 1}, {13, 9}, {5, 3}}) {
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h));
    const GBuffer g = frame_gbuffer(scene, bvh, w, h, 1, false);
    for (const char* spec : {"noopt", "ours", "ours:tile=4x4,k=16", "ours:tile=4x4,k=3", "contiguous:tile=16x16,k=7",
                             "sadeghi:interleave=2", "microjitter"})
      expect_gpu_generator_matches(scene, g, spec, device);
  }
  GBuffer empty = frame_gbuffer(scene, bvh, 16, 16, 0, false);
  for (ShadingPoint& sp : empty.points) sp = ShadingPoint{};
  empty.hits = 0;
  for (const char* spec : {"noopt", "ours", "sadeghi"}) expect_gpu_generator_matches(scene, empty, spec, device);
}

TEST(GpuGenerators, TakeTheCpuGeneratorsConfigAndRejectWhatTheGpuCannotDo) {
  EXPECT_NO_THROW(cuda::check_gpu_generator(*make_generator({"ours", "k=16,tile=16x8"})));
  EXPECT_NO_THROW(cuda::check_gpu_generator(*make_generator({"noopt", "order=scanline,tile=64x64"})));
  EXPECT_THROW(cuda::check_gpu_generator(*make_generator({"direct", ""})), Error);
  EXPECT_THROW(cuda::check_gpu_generator(*make_generator({"ours", "tile=64x64"})), Error);  // over one block
  for (const char* g : {"sadeghi", "microjitter"}) {
    EXPECT_NO_THROW(cuda::check_gpu_generator(*make_generator({g, "tile=64x64"}))) << g;            // any tile: a loop
    EXPECT_NO_THROW(cuda::check_gpu_generator(*make_generator({g, "order=scanline"}), true)) << g;  // fused too
  }
  // A fused block makes one tile's rays: ours / contiguous in scanline order have no fused form.
  for (const char* g : {"ours", "contiguous"}) {
    const std::string why = test::error_of([&] {
      cuda::check_gpu_generator(*make_generator({g, "order=scanline"}), true);
    });
    EXPECT_NE(why.find("order=scanline has no fused form"), std::string::npos) << why;
  }
  const std::string why = test::error_of([] { cuda::check_gpu_generator(*make_generator({"direct", ""})); });
  EXPECT_NE(why.find("GPU generators: noopt, ours, contiguous, sadeghi, microjitter"), std::string::npos) << why;
}

}  // namespace
}  // namespace raycoh
