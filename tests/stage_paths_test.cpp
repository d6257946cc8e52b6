// The stage model's trip-counted instruction terms (simt/stage_paths.h): nvcc's unrolled loops, the group
// kernel's regions run by the warps and trip counts of a workload, MLHCC's cut walks; hand-counted cases.
#include "simt/stage_paths.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "encoders/encoder.h"
#include "generators/generator.h"
#include "simt/gpu_model.h"
#include "simt/stage_model.h"
#include "tests/stage_hand_counts.h"

namespace raycoh {
namespace {

TEST(StagePaths, UnrolledLoopRunsSixteensThenFoursThenOnes) {
  const UnrolledLoop loop{100, 30, 10};
  EXPECT_DOUBLE_EQ(unrolled_loop_instructions(loop, 23), 100 + 30 + 3 * 10);  // 16 + 4 + 3
  EXPECT_DOUBLE_EQ(unrolled_loop_instructions(loop, 8), 2 * 30);
  EXPECT_DOUBLE_EQ(unrolled_loop_instructions(loop, 0), 0);
  EXPECT_DOUBLE_EQ(unrolled_loop_instructions(loop, -3), 0);
  // Without a 1x form the last iterations cost the 4x body's share each.
  EXPECT_DOUBLE_EQ(unrolled_loop_instructions(UnrolledLoop{0, 40, 0}, 6), 40 + 2 * 10);
  EXPECT_DOUBLE_EQ(unrolled_loop_instructions(UnrolledLoop{0, 0, 7}, 5), 35);
}

using test::hand_counts;

// 8x8 tiles (2 warps), k = 8 (8 groups, all in warp 0), 100 tiles, every pixel hit, all groups diffuse, duff.
TEST(StagePaths, GroupKernelAllDiffuseTileCountedByHand) {
  GroupPath p;
  p.k = 8;
  // Per tile: 2 x (common 100 + 2 x 2, member_rank 10 + 8 x 3) = 276; warp 0 alone: census 20 + 8 x 5, positions
  // 30 + 8 x 7, shared_mean 40 + 8 x 11 = 274; 2 x (reuse 50 + reuse_local 60) = 220. 770 / 2 warps.
  EXPECT_DOUBLE_EQ(group_path_instructions(hand_counts(), p, 64, 100), 385);
  // Half the pixels hit: the per-member loops run 4 times (positions 58, shared_mean 84): (276 + 202 + 220) / 2.
  p.hit_fraction = 0.5;
  EXPECT_DOUBLE_EQ(group_path_instructions(hand_counts(), p, 64, 100), 349);
}

TEST(StagePaths, GroupKernelRunsOnlyThePathOfItsRuleAndFrame) {
  GroupPath p;
  p.k = 8;
  // 50 groups off the all-diffuse path among 200 warps: a quarter of the warps run own_lobe (2 x 0.25 x 1000);
  // rotate runs reuse_rotate (70) instead of reuse_local (60): (276 + 274 + 500 + 2 x 120) / 2.
  p.nondiffuse_groups = 50;
  p.rotate = true;
  EXPECT_DOUBLE_EQ(group_path_instructions(hand_counts(), p, 64, 100), 645);
  // hybrid=glossy with 25 hybrid groups among 100 group-thread warps: 0.25 x (300 + 8 x 13 + 8 x 17) a tile.
  GroupPath g;
  g.k = 8;
  g.hybrid_glossy = true;
  g.hybrid_groups = 25;
  EXPECT_DOUBLE_EQ(group_path_instructions(hand_counts(), g, 64, 100), (770 + 135) / 2.0);
  // hybrid=independent: a quarter of the 200 warps run reuse_own (500) with 50 hybrid groups.
  GroupPath o;
  o.k = 8;
  o.hybrid_own = true;
  o.hybrid_groups = 50;
  EXPECT_DOUBLE_EQ(group_path_instructions(hand_counts(), o, 64, 100), (770 + 2 * 0.25 * 500) / 2.0);
}

TEST(StagePaths, GroupKernelLoopsRunKTimes) {
  GroupPath p;
  p.k = 64;  // one group in the 8x8 tile
  // 2 x (104 + 10 + 64 x 3) = 612; census 20 + 64 x 5, positions 30 + 64 x 7, shared_mean 40 + 64 x 11 = 1562;
  // reuse 220: 2394 / 2.
  EXPECT_DOUBLE_EQ(group_path_instructions(hand_counts(), p, 64, 100), 1197);
  // A 16x16 tile (8 warps, 4 groups): the warps loop runs 8 times; warp 0 alone holds the group threads.
  const double per_tile = 8 * (100 + 8 * 2 + 10 + 64 * 3) + 1562 + 8 * 110;
  EXPECT_DOUBLE_EQ(group_path_instructions(hand_counts(), p, 256, 100), per_tile / 8);
}

double region_total(const PathRegion& r) {
  double n = r.straight;
  for (const UnrolledLoop& l : r.loop) n += l.body16 + l.body4 + l.body1;
  return n;
}

double total(const GroupPathCounts& c) {
  return region_total(c.common) + region_total(c.member_rank) + region_total(c.census) + region_total(c.positions) +
         region_total(c.shared_mean) + region_total(c.shared_glossy) + region_total(c.own_lobe) +
         region_total(c.reuse) + region_total(c.reuse_own) + region_total(c.reuse_rotate) + region_total(c.reuse_local);
}

// Every instruction once is the static count of scripts/count-stage-instructions (the same SASS).
TEST(StagePaths, RegionsAddUpToTheStaticCount) {
  EXPECT_DOUBLE_EQ(total(group_paths_sm90()), 7186);
  EXPECT_DOUBLE_EQ(total(group_paths_sm90_fields60()), 7241);
  EXPECT_DOUBLE_EQ(total(group_paths_sm86()), 7015);
  EXPECT_DOUBLE_EQ(total(group_paths_sm86_fields60()), 7068);
  const GpuModelConfig h200 = gpu_preset("h200");
  EXPECT_DOUBLE_EQ(total(h200.stages.group_paths), h200.stages.group);
  EXPECT_DOUBLE_EQ(total(h200.stages.group_paths_fields60), h200.stages.group_fields60);
}

TEST(StagePaths, MlhccWalksAddTheirLoopBodies) {
  const double body[2] = {134, 135};
  EXPECT_DOUBLE_EQ(mlhcc_walk_instructions(536, body, KeyWalks{12, 17}), 536 + 11 * 134 + 16 * 135);
  EXPECT_DOUBLE_EQ(mlhcc_walk_instructions(536, body, KeyWalks{}), 536);  // unknown: the static count
  EXPECT_DOUBLE_EQ(mlhcc_walk_instructions(536, body, KeyWalks{1, 1}), 536);
}

TEST(StagePaths, StageModelUsesThePathWhenTheWorkloadGivesIt) {
  const GpuModelConfig gpu = gpu_preset("h200");
  StageWork w;
  w.width = 64;
  w.height = 32;
  w.rays = 64 * 32;
  w.grouping = true;
  const double warps = 32 * 2;  // 32 tiles of 8x8
  EXPECT_DOUBLE_EQ(stage_generator_terms(gpu, w).issue_ms, stage_issue_ms(gpu, warps, gpu.stages.group));
  w.group_path.k = 8;
  const double path = group_path_instructions(gpu.stages.group_paths, w.group_path, 64, 32);
  EXPECT_LT(path, gpu.stages.group);
  EXPECT_DOUBLE_EQ(stage_generator_terms(gpu, w).issue_ms, stage_issue_ms(gpu, warps, path));
  StageWork k;
  k.rays = 3200;
  k.key = KeyKind::Mlhcc;
  k.key_bits = 32;
  const double plain = stage_key_ms(gpu, k);
  k.mlhcc_walks = KeyWalks{12, 17};
  const double cycles = 536 + 11 * 134 + 16 * 135;
  EXPECT_DOUBLE_EQ(stage_key_ms(gpu, k) - plain,
                   stage_issue_ms(gpu, 100, cycles) -
                       std::max(stage_issue_ms(gpu, 100, 536), stage_stream_ms(gpu, key_bytes(3200, 32))));
}

NooptPathCounts noopt_hand_counts() {
  NooptPathCounts c;
  c.common.straight = 100;
  c.common.loop[0] = {0, 0, 2};
  c.diffuse.straight = 10;
  c.glossy.straight = 1000;
  c.transmissive.straight = 300;
  c.tail.straight = 50;
  return c;
}

// 8x8 tiles (2 warps), 100 tiles: 200 warps.
TEST(StagePaths, NooptRunsTheLobesItsWarpsHold) {
  NooptPath p{true, 0, 0};
  EXPECT_DOUBLE_EQ(noopt_path_instructions(noopt_hand_counts(), p, 64, 100), 100 + 2 * 2 + 10);
  p.glossy_groups = 50;        // a quarter of the warps
  p.transmissive_groups = 20;  // a tenth
  EXPECT_DOUBLE_EQ(noopt_path_instructions(noopt_hand_counts(), p, 64, 100), 114 + 250 + 30 + 0.35 * 50);
  p.glossy_groups = 400;  // capped: every warp
  p.transmissive_groups = 100;
  EXPECT_DOUBLE_EQ(noopt_path_instructions(noopt_hand_counts(), p, 64, 100), 114 + 1000 + 150 + 50);
  // A scanline row (1920 x 1) runs blocks of 256 threads: the warps loop 8 times.
  EXPECT_DOUBLE_EQ(noopt_path_instructions(noopt_hand_counts(), NooptPath{true, 0, 0}, 1920, 1080), 100 + 16 + 10);
}

double total(const NooptPathCounts& c) {
  return region_total(c.common) + region_total(c.diffuse) + region_total(c.glossy) + region_total(c.transmissive) +
         region_total(c.tail);
}

TEST(StagePaths, NooptRegionsAddUpToTheStaticCount) {
  EXPECT_DOUBLE_EQ(total(noopt_paths_sm90()), 1599);
  EXPECT_DOUBLE_EQ(total(noopt_paths_sm90_fields60()), 1620);
  EXPECT_DOUBLE_EQ(total(noopt_paths_sm86()), 1577);
  EXPECT_DOUBLE_EQ(total(noopt_paths_sm86_fields60()), 1604);
  const GpuModelConfig h200 = gpu_preset("h200");
  EXPECT_DOUBLE_EQ(total(h200.stages.noopt_paths), h200.stages.noopt);
  StageWork w;
  w.width = 64;
  w.height = 32;
  w.rays = 64 * 32;
  EXPECT_DOUBLE_EQ(stage_generator_terms(h200, w).issue_ms, stage_issue_ms(h200, 64, h200.stages.noopt));
  w.noopt_path = NooptPath{true, 0, 0};
  EXPECT_DOUBLE_EQ(stage_generator_terms(h200, w).issue_ms, stage_issue_ms(h200, 64, 509 + 2 * 21 / 4.0 + 159));
}

TEST(StagePaths, StageWorkTakesTheGeneratorsPathAndThePassGroupCounts) {
  const auto none = make_encoder({"none", ""}, EncoderContext{});
  GenerationStats stats;
  stats.groups[static_cast<int>(GroupType::Glossy)] = 3;
  stats.groups[static_cast<int>(GroupType::Hybrid)] = 2;
  stats.groups[static_cast<int>(GroupType::Independent)] = 1;
  stats.groups[static_cast<int>(GroupType::Diffuse)] = 40;
  const StageWork w =
      stage_work(*make_generator({"ours", "k=16,frame=rotate,hybrid=glossy"}), *none, false, 64, 32, 100, &stats);
  EXPECT_EQ(w.group_path.k, 16);
  EXPECT_TRUE(w.group_path.rotate);
  EXPECT_TRUE(w.group_path.hybrid_glossy);
  EXPECT_FALSE(w.group_path.hybrid_own);
  EXPECT_DOUBLE_EQ(w.group_path.nondiffuse_groups, 6);
  EXPECT_DOUBLE_EQ(w.group_path.hybrid_groups, 2);
  EXPECT_EQ(stage_work(*make_generator({"noopt", ""}), *none, false, 64, 32, 100, &stats).group_path.k, 0);
}

}  // namespace
}  // namespace raycoh
