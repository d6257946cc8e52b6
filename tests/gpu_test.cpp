// CUDA path: the kernel runs core/traverse.h and must return exactly the CPU tracer's hits. Skips without a GPU.
#include <gtest/gtest.h>

#include <cstring>

#include "bvh/bvh_build.h"
#include "cuda/cuda_device.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "generators/primary.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "tests/gpu_test_size.h"
#include "tests/test_util.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

void expect_gpu_matches_cpu(const std::string& spec) {
  const Scene scene = load_scene(spec);
  const Bvh bvh = build_bvh(scene);
  auto cpu = make_tracer({"cpu", ""}, scene, bvh);
  const int width = test::gpu_test_size(256, 64), height = test::gpu_test_size(192, 48);
  const auto order = make_pixel_order(width, height, RayOrder::Tile, 8, 8);
  const FirstHits first = first_hits(scene, *cpu, width, height, order, 1, 0);
  const PixelRays& primary = first.primary;
  std::vector<Hit> cpu_hits = first.hits;  // reused below for other batches
  std::vector<Hit> gpu_hits(primary.rays.size());
  float ms = 0;
  cuda::trace_closest(bvh.view(), primary.rays.data(), primary.rays.size(), gpu_hits.data(), &ms);
  EXPECT_EQ(std::memcmp(cpu_hits.data(), gpu_hits.data(), cpu_hits.size() * sizeof(Hit)), 0) << spec;

  const GBuffer& g = first.gbuffer;
  RayBatch batch;
  GenerationStats stats;
  make_generator({"noopt", ""})->generate(scene, g, 1, batch, stats);
  cpu_hits.resize(batch.size());
  gpu_hits.resize(batch.size());
  cpu->trace(batch.rays.data(), batch.size(), cpu_hits.data());
  cuda::trace_closest(bvh.view(), batch.rays.data(), batch.size(), gpu_hits.data(), &ms);
  size_t differ = 0;
  for (size_t i = 0; i < batch.size(); ++i) differ += std::memcmp(&cpu_hits[i], &gpu_hits[i], sizeof(Hit)) != 0;
  EXPECT_EQ(differ, 0u) << spec << ": " << differ << " of " << batch.size() << " secondary hits differ";
}

TEST(Gpu, HitsEqualTheCpuTracerBitForBit) {
  if (cuda::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  expect_gpu_matches_cpu("cornell");
  expect_gpu_matches_cpu("voxels:size=48");
  for (const auto& path : test::shared_scene_files())
    if (path.filename() == "sibenik.glb") expect_gpu_matches_cpu(path.string());
}

}  // namespace
}  // namespace raycoh
