// The reordering step on the GPU (cuda/device_keys.h) against the CPU encoders (encoders/*.cpp) and radix sort:
// keys of every key encoder and parameter variant equal the CPU's bit for bit (origin, aila, twopoint, mlhcc) or
// differ only in their direction bits on the rare rays where CUDA's atan2f/acosf round differently from glibc's
// (reis, costa; bounded and printed); CUB's sort of the CPU keys gives exactly the CPU's stable order; the whole
// device step (keys, sort, gather) equals reorder() in Physical mode. Skips cleanly without a GPU; label `gpu`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "core/rng.h"
#include "cuda/cuda_device.h"
#include "cuda/device_keys.h"
#include "encoders/encoder.h"
#include "encoders/reorder.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "tests/gpu_test_size.h"
#include "tests/test_util.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

#define SKIP_WITHOUT_GPU() \
  if (cuda::device_count() == 0) GTEST_SKIP() << "no CUDA device"

RayBatch secondary_batch(const Scene& scene, const Bvh& bvh, const std::string& generator) {
  const int width = test::gpu_test_size(256, 48), height = test::gpu_test_size(192, 32);
  const GBuffer g = first_hits(scene, *make_tracer({"cpu", ""}, scene, bvh), width, height,
                               make_pixel_order(width, height, RayOrder::Tile, 8, 8), 1, 0)
                        .gbuffer;
  RayBatch batch;
  GenerationStats stats;
  make_generator(parse_plugin_spec(generator))->generate(scene, g, 1, batch, stats);
  return batch;
}

// Keys whose GPU value may differ from the CPU's where libm differs, and the bits that must agree regardless.
bool uses_libm_angles(const std::string& name) { return name == "reis" || name == "costa"; }
uint64_t origin_bits_mask(const std::string& name, int key_bits) {
  const uint64_t all = key_bits == 64 ? ~0ull : (1ull << key_bits) - 1;
  if (name == "reis") return all & ~((1ull << (key_bits - 22)) - 1);  // the top 22 bits hold the origin
  if (name == "costa") return all >> 8;                               // the top 8 bits hold the direction
  return all;
}

// order sorts keys stably by value: sorted[i] = keys[order[i]], non-decreasing, equal keys in index order.
void expect_stable_sort(const std::vector<uint64_t>& keys, const std::vector<uint64_t>& sorted,
                        const std::vector<uint32_t>& order) {
  ASSERT_EQ(order.size(), keys.size());
  std::vector<bool> seen(keys.size(), false);
  for (size_t i = 0; i < order.size(); ++i) {
    ASSERT_LT(order[i], keys.size());
    ASSERT_FALSE(seen[order[i]]);
    seen[order[i]] = true;
    ASSERT_EQ(sorted[i], keys[order[i]]);
    if (i > 0) {
      ASSERT_LE(sorted[i - 1], sorted[i]);
      if (sorted[i - 1] == sorted[i]) {
        ASSERT_LT(order[i - 1], order[i]);
      }
    }
  }
}

void expect_encoder_matches(const Scene& scene, const Bvh& bvh, const RayBatch& batch, const std::string& spec_text) {
  SCOPED_TRACE(spec_text);
  const PluginSpec spec = parse_plugin_spec(spec_text);
  auto encoder = make_encoder(spec, EncoderContext{scene.bounds, &bvh});
  const int bits = encoder->key_bits();
  const size_t n = batch.size();
  std::vector<uint64_t> cpu_keys(n);
  encoder->encode(batch, cpu_keys.data());
  RayBatch cpu_sorted;
  std::vector<uint32_t> cpu_order;
  ReorderTimings cpu_times;
  ASSERT_TRUE(reorder(*encoder, batch, PermuteMode::Physical, cpu_sorted, cpu_order, cpu_times));
  const std::vector<uint64_t> cpu_sorted_keys = encoder->workspace().keys;

  cuda::DeviceKeys device(encoder->recipe(), &bvh);
  ASSERT_EQ(device.key_bits(), bits);

  // Keys.
  std::vector<uint64_t> gpu_keys(n);
  device.keys(batch.rays.data(), n, gpu_keys.data());
  size_t differ = 0, differ_outside_direction = 0;
  const uint64_t must_agree = origin_bits_mask(spec.name, bits);
  for (size_t i = 0; i < n; ++i) {
    if (gpu_keys[i] == cpu_keys[i]) continue;
    ++differ;
    differ_outside_direction += ((gpu_keys[i] ^ cpu_keys[i]) & must_agree) != 0;
  }
  if (uses_libm_angles(spec.name)) {
    std::printf("    %-40s %zu of %zu keys differ (atan2f/acosf rounding)\n", spec_text.c_str(), differ, n);
    EXPECT_EQ(differ_outside_direction, 0u);
    EXPECT_LE(differ, bits == 32 ? n / 1000 + 3 : n / 10 + 3);
  } else {
    EXPECT_EQ(differ, 0u) << differ << " of " << n << " keys differ";
  }

  // CUB's sort of the CPU keys is the CPU's stable sort.
  std::vector<uint64_t> sorted(n);
  std::vector<uint32_t> order(n);
  device.sort(cpu_keys.data(), n, sorted.data(), order.data());
  EXPECT_EQ(order, cpu_order);
  EXPECT_EQ(sorted, cpu_sorted_keys);

  // The whole device step.
  std::vector<Ray> sorted_rays(n);
  cuda::GpuReorderTimings times;
  device.reorder(batch.rays.data(), n, sorted.data(), order.data(), sorted_rays.data(), times);
  EXPECT_GE(times.key_ms, 0.f);
  EXPECT_GE(times.sort_ms, 0.f);
  EXPECT_GE(times.permute_ms, 0.f);
  expect_stable_sort(gpu_keys, sorted, order);
  if (differ == 0) {
    EXPECT_EQ(order, cpu_order);
    EXPECT_EQ(std::memcmp(sorted_rays.data(), cpu_sorted.rays.data(), n * sizeof(Ray)), 0);
  }
}

const std::vector<std::string>& encoder_specs() {
  static const std::vector<std::string> specs = {"origin",
                                                 "origin:bits=64",
                                                 "reis",
                                                 "reis:bits=64",
                                                 "costa",
                                                 "costa:bits=64",
                                                 "aila",
                                                 "aila:bits=64",
                                                 "twopoint",
                                                 "twopoint:L=1",
                                                 "twopoint:bits=64",
                                                 "mlhcc",
                                                 "mlhcc:bits=64",
                                                 "mlhcc:points=origin",
                                                 "mlhcc:ranks=global,lambda=0.3"};
  return specs;
}

TEST(GpuKeys, KeysAndOrderEqualTheCpuEncoders) {
  SKIP_WITHOUT_GPU();
  std::vector<std::string> scenes = {"cornell", "voxels:size=48"};
  for (const auto& path : test::shared_scene_files())
    if (path.filename() == "sibenik.glb") scenes.push_back(path.string());
  for (const std::string& name : scenes) {
    SCOPED_TRACE(name);
    const Scene scene = load_scene(name);
    const Bvh bvh = build_bvh(scene);
    for (const char* generator : {"noopt", "ours"}) {
      SCOPED_TRACE(generator);
      const RayBatch batch = secondary_batch(scene, bvh, generator);
      for (const std::string& spec : encoder_specs()) expect_encoder_matches(scene, bvh, batch, spec);
    }
  }
}

// Many equal keys (stability) and keys of 32 and 64 bits, against std::stable_sort; an empty input.
TEST(GpuKeys, RadixSortIsStableOverTheKeyBits) {
  SKIP_WITHOUT_GPU();
  for (int bits : {32, 64}) {
    SCOPED_TRACE(bits);
    KeyRecipe config;
    config.kind = KeyKind::Origin;
    config.bits = bits;
    cuda::DeviceKeys device(config, nullptr);
    const size_t n = test::gpu_test_size<size_t>(1000003, 10007);
    std::vector<uint64_t> keys(n);
    for (size_t i = 0; i < n; ++i) {
      const uint64_t r =
          (uint64_t{rng_u32(9, 0, static_cast<uint32_t>(i), 0)} << 32) | rng_u32(9, 0, static_cast<uint32_t>(i), 1);
      keys[i] = i % 3 == 0 ? r % 1000 : (bits == 32 ? r & 0xFFFFFFFFull : r);
    }
    std::vector<uint32_t> expected(n);
    std::iota(expected.begin(), expected.end(), 0u);
    std::stable_sort(expected.begin(), expected.end(), [&](uint32_t a, uint32_t b) { return keys[a] < keys[b]; });
    std::vector<uint64_t> sorted(n);
    std::vector<uint32_t> order(n);
    device.sort(keys.data(), n, sorted.data(), order.data());
    EXPECT_EQ(order, expected);
    device.sort(keys.data(), 0, sorted.data(), order.data());  // nothing to do, no error
  }
}

// Both refusals come before any CUDA call, so this runs without a GPU too.
TEST(GpuKeys, NoneMakesNoKeys) {
  EXPECT_THROW(cuda::DeviceKeys(KeyRecipe{}, nullptr), Error);
  KeyRecipe mlhcc;
  mlhcc.kind = KeyKind::Mlhcc;
  mlhcc.bits = 32;
  EXPECT_THROW(cuda::DeviceKeys(mlhcc, nullptr), Error);  // mlhcc needs the BVH
}

}  // namespace
}  // namespace raycoh
