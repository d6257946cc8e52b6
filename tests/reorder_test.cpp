// reorder() end to end: a stable sort by key that permutes every array of the batch (physical) or only gives
// the order (indirect), the none encoder and empty or one-ray batches, and keys and order independent of the
// thread count.
#include "encoders/reorder.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "encoders/encoder.h"
#include "scenes/scene.h"
#include "tests/encoder_test_util.h"

namespace raycoh {
namespace {

using test::box_of;
using test::kUnitBox;
using test::make_batch;
using test::random_rays;
using test::random_unit;
using test::ray;
using test::tiny_bvh;

TEST(Reorder, SortsByKeyStablyAndPermutesEveryArray) {
  const Bounds box = box_of({0, 0, 0}, {4, 4, 4});
  // Few distinct keys (origins on a 2x2x2 grid), so stability is exercised.
  std::vector<Ray> rays;
  std::mt19937 rng(9);
  for (int i = 0; i < 3000; ++i)
    rays.push_back(ray({float(rng() % 2) * 2.f, float(rng() % 2) * 2.f, float(rng() % 2) * 2.f}, random_unit(rng)));
  RayBatch in = make_batch(rays);
  for (size_t i = 0; i < in.size(); ++i) {  // a grouping generator's arrays travel with their rays too
    in.tile.push_back(static_cast<uint32_t>(i / 64));
    in.group.push_back(static_cast<uint32_t>(i / 4));
    in.group_type.push_back(static_cast<GroupType>(i % 3));
  }
  for (const char* spec : {"origin", "reis:bits=64", "costa", "aila", "twopoint"}) {
    auto encoder = make_encoder(parse_plugin_spec(spec), EncoderContext{box, nullptr});
    std::vector<uint64_t> keys(in.size());
    encoder->encode(in, keys.data());
    for (PermuteMode mode : {PermuteMode::Physical, PermuteMode::Indirect}) {
      RayBatch out;
      std::vector<uint32_t> order;
      ReorderTimings t;
      ASSERT_TRUE(reorder(*encoder, in, mode, out, order, t));
      ASSERT_TRUE(is_index_permutation(order, in.size()));
      std::vector<uint32_t> expected(in.size());
      std::iota(expected.begin(), expected.end(), 0u);
      std::stable_sort(expected.begin(), expected.end(), [&](uint32_t a, uint32_t b) { return keys[a] < keys[b]; });
      ASSERT_EQ(order, expected) << spec;
      for (size_t i = 0; i < in.size(); ++i) ASSERT_EQ(encoder->workspace().keys[i], keys[order[i]]);
      EXPECT_GE(t.key_ms, 0.0);
      EXPECT_GE(t.sort_ms, 0.0);
      if (mode == PermuteMode::Indirect) {
        EXPECT_EQ(t.permute_ms, 0.0);
        EXPECT_EQ(out.size(), 0u);
        continue;
      }
      ASSERT_EQ(out.size(), in.size());
      EXPECT_EQ(out.width, in.width);
      ASSERT_EQ(out.tile.size(), in.size());
      ASSERT_EQ(out.group.size(), in.size());
      ASSERT_EQ(out.group_type.size(), in.size());
      for (size_t i = 0; i < in.size(); ++i) {
        const uint32_t j = order[i];
        ASSERT_EQ(out.rays[i].org.x, in.rays[j].org.x);
        ASSERT_EQ(out.rays[i].dir.z, in.rays[j].dir.z);
        ASSERT_EQ(out.pixel[i], in.pixel[j]);
        ASSERT_EQ(out.pdf[i], in.pdf[j]);
        ASSERT_EQ(out.material[i], in.material[j]);
        ASSERT_EQ(out.tile[i], in.tile[j]);
        ASSERT_EQ(out.group[i], in.group[j]);
        ASSERT_EQ(out.group_type[i], in.group_type[j]);
      }
    }
  }
}

TEST(Reorder, NoneEmptyAndOneRayBatches) {
  const Bvh bvh = tiny_bvh();
  const EncoderContext ctx{kUnitBox, &bvh};
  RayBatch out;
  std::vector<uint32_t> order = {7, 7};
  ReorderTimings t{1, 2, 3};
  auto none = make_encoder(parse_plugin_spec("none"), ctx);
  EXPECT_FALSE(reorder(*none, make_batch({ray({0, 0, 0}, {1, 0, 0})}), PermuteMode::Physical, out, order, t));
  EXPECT_TRUE(order.empty());
  EXPECT_EQ(t.total_ms(), 0.0);
  for (const char* name : {"origin", "reis", "costa", "aila", "twopoint", "mlhcc"}) {
    auto encoder = make_encoder(parse_plugin_spec(name), ctx);
    for (size_t n : {0, 1}) {
      const RayBatch in = make_batch(n ? std::vector<Ray>{ray({0.3f, 0.2f, 0.1f}, {0, 0, 1})} : std::vector<Ray>{});
      ASSERT_TRUE(reorder(*encoder, in, PermuteMode::Physical, out, order, t)) << name;
      EXPECT_EQ(order.size(), n);
      EXPECT_EQ(out.size(), n);
      if (n) {
        EXPECT_EQ(order[0], 0u);
      }
    }
  }
}

TEST(Reorder, KeysAndOrderDoNotDependOnTheThreadCount) {
  const Scene scene = load_scene("cornell");
  const Bvh bvh = build_bvh(scene);
  const RayBatch in = make_batch(random_rays(scene.bounds, 200000, 13));
  for (const char* spec : {"aila", "mlhcc"}) {
    std::vector<std::vector<uint32_t>> orders;
    for (int threads : {1, 2, 7}) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      auto encoder = make_encoder(parse_plugin_spec(spec), EncoderContext{scene.bounds, &bvh});
      RayBatch out;
      std::vector<uint32_t> order;
      ReorderTimings t;
      reorder(*encoder, in, PermuteMode::Physical, out, order, t);
      orders.push_back(order);
    }
    EXPECT_EQ(orders[0], orders[1]) << spec;
    EXPECT_EQ(orders[0], orders[2]) << spec;
  }
}

}  // namespace
}  // namespace raycoh
