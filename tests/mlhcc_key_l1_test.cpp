// The MODELED L1 replay of MLHCC's key kernel (bench/mlhcc_key_l1.h) on hand-countable warps: a request's sectors
// are the distinct 32-byte sectors of its active lanes, a second warp loading the same node hits, 32 lanes on 32
// nodes make 32 sectors a load, each SM has its own L1, and record_walk names the loads mlhcc_write_path makes.
#include "bench/mlhcc_key_l1.h"

#include <gtest/gtest.h>

namespace raycoh::keyl1 {
namespace {

CacheModelConfig small_gpu(uint32_t sms) {
  CacheModelConfig c;
  c.sms = sms;
  c.l1.bytes = 256 * 1024;
  c.l1.ways = l1_ways_for(c.l1.bytes, c.line_bytes);
  c.l2.bytes = 1 << 20;
  c.l2.ways = 16;
  return c;
}

// A warp whose first `lanes` lanes read rays first.. and, in one origin iteration, node nodes[i].
Warp one_iteration(uint64_t first_ray, const std::vector<int32_t>& nodes) {
  Warp w;
  for (size_t i = 0; i < nodes.size(); ++i) {
    w[i].active = true;
    w[i].ray = first_ray + i;
    w[i].walk[0].push_back(WalkStep{nodes[i], 0, false, false});
  }
  return w;
}

TEST(MlhccKeyL1, LayoutIsAlignedAndOrdered) {
  const Layout l = packed_layout(3, 5);
  EXPECT_EQ(l.rays % 256, 0u);
  EXPECT_EQ(l.nodes, 256u + 256u);    // 3 rays = 96 bytes, rounded up
  EXPECT_EQ(l.cuts, l.nodes + 512u);  // 5 nodes = 320 bytes, rounded up
}

TEST(MlhccKeyL1, TwoWarpsOnOneNodeTheSecondHits) {
  Replay r(small_gpu(1), packed_layout(64, 8));
  const std::vector<Warp> warps = {one_iteration(0, {5}), one_iteration(1, {5})};
  r.replay_group(0, warps.data(), warps.size());
  const Counts& c = r.counts();
  EXPECT_EQ(c.warps, 2u);
  // Ray: 7 loads of one lane a warp, one sector each; rays 0 and 1 are in different 32-byte sectors.
  EXPECT_EQ(c.requests[kRay], 14u);
  EXPECT_EQ(c.sectors[kRay], 14u);
  EXPECT_EQ(c.misses[kRay], 2u);
  EXPECT_EQ(c.pending[kRay], 12u);  // each warp's 6 later loads of the sector it just missed
  // Node: 12 box loads a warp, one sector each (bytes 0..31 and 32..47 of node 5: two sectors); warp 1 misses
  // both once, warp 2 hits both.
  EXPECT_EQ(c.requests[kNode], 24u);
  EXPECT_EQ(c.sectors[kNode], 24u);
  EXPECT_EQ(c.misses[kNode], 2u);
  EXPECT_EQ(c.pending[kNode], 10u);  // warp 1's 10 later box loads; warp 2's hits are on warp 1's step
  // Cut: the level word only (no rank: rank = false), one sector.
  EXPECT_EQ(c.requests[kCut], 2u);
  EXPECT_EQ(c.misses[kCut], 1u);
  EXPECT_EQ(c.miss_steps[kNode], 1u);
  EXPECT_EQ(c.l2_misses, 2u + 2u + 1u);  // cold L2: every L1 miss is a DRAM sector
}

TEST(MlhccKeyL1, ThirtyTwoLanesOnThirtyTwoNodesMakeThirtyTwoSectors) {
  std::vector<int32_t> nodes;
  for (int32_t i = 0; i < 32; ++i) nodes.push_back(i);
  Replay r(small_gpu(1), packed_layout(32, 32));
  const Warp w = one_iteration(0, nodes);
  r.replay_group(0, &w, 1);
  const Counts& c = r.counts();
  EXPECT_EQ(c.requests[kNode], 12u);
  EXPECT_EQ(c.sectors[kNode], 12u * 32u);  // 64-byte nodes: every lane's word in a sector of its own
  EXPECT_EQ(c.misses[kNode], 64u);         // two sectors of each node
  EXPECT_EQ(c.sectors[kRay], 7u * 32u);    // 32-byte rays: 32 sectors a load
  EXPECT_EQ(c.misses[kRay], 32u);
  EXPECT_EQ(c.sectors[kCut], 16u);  // 16-byte cut records: two lanes a sector
}

TEST(MlhccKeyL1, EachSmHasItsOwnL1) {
  Replay r(small_gpu(2), packed_layout(64, 8));
  const Warp a = one_iteration(0, {3}), b = one_iteration(32, {3});
  r.replay_group(0, &a, 1);
  r.replay_group(1, &b, 1);
  EXPECT_EQ(r.counts().misses[kNode], 4u);  // both SMs miss node 3's two sectors
  EXPECT_EQ(r.counts().l2_misses, 5u);      // rays 0 and 32, node 3's two sectors, cut 3's one: the L2 misses each once
}

TEST(MlhccKeyL1, RankAndChildLoadsOnlyInTheLanesThatMakeThem) {
  Warp w = one_iteration(0, {0, 0});
  w[0].walk[0][0] = WalkStep{0, 1, true, true};  // rank word at byte 4, child reference at node byte 52
  Replay r(small_gpu(1), packed_layout(32, 1));
  r.replay_group(0, &w, 1);
  const Counts& c = r.counts();
  EXPECT_EQ(c.requests[kCut], 2u);    // the level word (both lanes), the rank (lane 0)
  EXPECT_EQ(c.requests[kNode], 13u);  // 12 box loads, the child reference (lane 0)
  EXPECT_EQ(c.misses[kNode], 2u);     // the child reference is in the boxes' second sector
}

// One inner root whose children are both leaves, each in cut level 1 (1 bit, offset 0).
TEST(MlhccKeyL1, RecordWalkNamesTheLoopsLoads) {
  BvhNode root;
  root.lo0 = {0, 0, 0};
  root.hi0 = {1, 1, 1};
  root.lo1 = {2, 0, 0};
  root.hi1 = {3, 1, 1};
  root.child[0] = ~0;
  root.child[1] = ~1;
  MlhccNodeCut cut;
  cut.level[0] = cut.level[1] = 1;
  cut.rank[1] = 1;
  MlhccCuts cuts;
  cuts.nodes = &root;
  cuts.cuts = &cut;
  cuts.node_count = 1;
  cuts.level_count = 1;
  cuts.level_bits[0] = 1;
  std::vector<WalkStep> steps;
  record_walk(cuts, Vec3{2.5f, 0.5f, 0.5f}, 2, 1, 32, steps);
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_EQ(steps[0].node, 0);
  EXPECT_EQ(steps[0].child, 1);
  EXPECT_TRUE(steps[0].rank);
  EXPECT_TRUE(steps[0].next);
  EXPECT_TRUE(walk_is_consistent(cuts, steps));
  record_walk(cuts, Vec3{0.5f, 0.5f, 0.5f}, 2, 1, 1, steps);  // offset 2 x 0 + 1 x 1 = 1 >= 1 bit: stops
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_EQ(steps[0].child, 0);
  EXPECT_FALSE(steps[0].rank);
  EXPECT_FALSE(steps[0].next);
  EXPECT_TRUE(walk_is_consistent(cuts, steps));
  steps.push_back(steps[0]);  // an iteration after one that did not load the child: no loop makes it
  EXPECT_FALSE(walk_is_consistent(cuts, steps));
}

}  // namespace
}  // namespace raycoh::keyl1
