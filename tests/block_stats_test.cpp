// The per-block z-test of shading/block_stats.h that the device path tracer's images are held to: its numbers on
// hand-made frames, its edge cases, and on the CPU path tracer that two seeds agree and a 10% brighter image
// does not.
#include "shading/block_stats.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "generators/generator.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "tests/block_stats_util.h"
#include "tests/shading_test_util.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

std::vector<Vec3> constant(int w, int h, Vec3 v) { return std::vector<Vec3>(static_cast<size_t>(w) * h, v); }

TEST(BlockStats, BlockMeansAndVarianceOverFrames) {
  // 3x2 image, 2-pixel blocks: blocks (0,0) 2x2 pixels, (1,0) 1x2 (clipped).
  BlockFrameStats s(3, 2, 2);
  ASSERT_EQ(s.blocks_x(), 2);
  ASSERT_EQ(s.blocks_y(), 1);
  std::vector<Vec3> f = constant(3, 2, Vec3(1.f));
  f[2] = Vec3(5.f);  // pixel (2, 0): block 1
  s.add_frame(f);    // block 0 mean 1, block 1 mean (5 + 1) / 2 = 3
  f = constant(3, 2, Vec3(3.f));
  s.add_frame(f);  // block 0: 3, block 1: 3
  f = constant(3, 2, Vec3(2.f));
  s.add_frame(f);  // block 0: 2, block 1: 2
  EXPECT_DOUBLE_EQ(s.mean(0, 0), 2.0);
  EXPECT_DOUBLE_EQ(s.variance(0, 1), 1.0);  // (1 + 1 + 0) / 2
  EXPECT_NEAR(s.mean(1, 2), 8.0 / 3.0, 1e-12);
  EXPECT_NEAR(s.variance(1, 2), (1.0 / 9 + 1.0 / 9 + 4.0 / 9) / 2.0, 1e-12);
  EXPECT_EQ(s.frames(), 3u);
}

TEST(BlockStats, NonFiniteSamplesAreCountedAndLeftOut) {
  BlockFrameStats s(2, 1, 8);
  std::vector<Vec3> f = {Vec3(4.f), Vec3(std::numeric_limits<float>::quiet_NaN())};
  s.add_frame(f);
  s.add_frame(f);
  EXPECT_EQ(s.non_finite(), 2u);
  EXPECT_DOUBLE_EQ(s.mean(0, 0), 4.0);
  EXPECT_THROW(s.add_frame(constant(3, 1, Vec3(0.f))), Error);
  EXPECT_THROW(BlockFrameStats(0, 4), Error);
}

TEST(BlockStats, ZIsWelchsStatisticAndFlagsBlocksBeyondTheLimit) {
  BlockFrameStats a(1, 1), b(1, 1);
  for (float v : {1.f, 2.f, 3.f, 4.f}) a.add_frame({Vec3(v)});                        // mean 2.5, var 5/3
  for (float v : {3.f, 4.f, 5.f, 6.f}) b.add_frame({Vec3(v, 2.5f + (v - 4.5f), v)});  // mean 4.5, var 5/3
  const BlockZTest t = block_z_test(a, b, 2.0);
  const double expect = -2.0 / std::sqrt(2.0 * (5.0 / 3.0) / 4.0);
  EXPECT_NEAR(t.z[0], expect, 1e-12);
  EXPECT_NEAR(t.z[1], 0.0, 1e-12);
  EXPECT_NEAR(t.max_abs_z, -expect, 1e-12);
  EXPECT_EQ(t.beyond, 2u);  // red and blue: |z| = 2.19 > 2
  EXPECT_EQ(t.worst_channel, 0);
  EXPECT_FALSE(t.summary().empty());
  EXPECT_EQ(block_z_test(a, b, 3.0).beyond, 0u);
}

TEST(BlockStats, ConstantBlocksAreEqualOrInfinitelyApart) {
  BlockFrameStats a(1, 1), b(1, 1), c(1, 1);
  for (int f = 0; f < 3; ++f) {
    a.add_frame({Vec3(1.f)});
    b.add_frame({Vec3(1.f)});
    c.add_frame({Vec3(1.f, 1.f, 2.f)});
  }
  EXPECT_EQ(block_z_test(a, b, 4.0).max_abs_z, 0.0);
  const BlockZTest t = block_z_test(a, c, 4.0);
  EXPECT_TRUE(std::isinf(t.z[2]));
  EXPECT_EQ(t.beyond, 1u);
  BlockFrameStats one(1, 1);
  one.add_frame({Vec3(1.f)});
  EXPECT_THROW(block_z_test(a, one, 4.0), Error);
}

// Two seeds of the CPU path tracer are independent estimates of one image: no block beyond |z| = 4. The same
// render 10% brighter is not the same image, and the test must say so.
TEST(BlockStats, CpuRendersOfTwoSeedsAgreeAndABrighterOneDoesNot) {
  const Scene scene = load_scene("cornell");
  const Bvh bvh = build_bvh(scene);
  auto tracer = make_tracer({"cpu", ""}, scene, bvh);
  auto generator = make_generator({"noopt", ""});
  constexpr int kFrames = 128;
  const BlockFrameStats a = test::cpu_block_stats(scene, *tracer, *generator, test::small(32, 24, 1), kFrames);
  const BlockFrameStats b = test::cpu_block_stats(scene, *tracer, *generator, test::small(32, 24, 2), kFrames);
  const BlockFrameStats brighter =
      test::cpu_block_stats(scene, *tracer, *generator, test::small(32, 24, 2), kFrames, 1.1f);
  const BlockZTest same = block_z_test(a, b, 4.0);
  EXPECT_EQ(same.beyond, 0u) << same.summary();
  EXPECT_GT(same.max_abs_z, 0.0);  // different seeds: different samples
  const BlockZTest apart = block_z_test(a, brighter, 4.0);
  EXPECT_GT(apart.beyond, 0u) << apart.summary();
}

}  // namespace
}  // namespace raycoh
