// The SIMT warp model (simt/simt.h), step by step: hand-built warps on a hand-built BVH whose every step is known
// (one shared path, disjoint subtrees with Aila's speculative node walk, partial and rejected lanes, leaves of
// different sizes, straddling triangles). The `simt` tracer on real scenes is tests/simt_tracer_test.cpp.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "bvh/bvh_build.h"
#include "simt/simt.h"
#include "tests/test_util.h"
namespace raycoh {
namespace {

// ---- A hand-built BVH whose traversal is known step by step ----
//
//   node 0: [0,1.1]x[0,2] -> node 1             [0.9,2]x[0,2] -> node 2
//   node 1: [0,1.1]x[0,1] -> leaf {tri 0}       [0,1]x[1,2] -> leaf {tri 1}
//   node 2: [0.9,2]x[0,1] -> leaf {tri 2}       [1,2]x[1,2] -> node 3
//   node 3: [1,1.5]x[1,2] -> leaf {tri 3}       [1.5,2]x[1,2] -> leaf {tri 4, tri 5}
// All boxes span z in [0.5, 1.5]; the overlap around x = 1 lets a ray enter both halves. Rays go +z from z = 0:
//   ray A at (0.5, 0.5): nodes 0, 1; leaf {0}; hits tri 0 at t = 1.      nodes 2, leaves 1, triangles 1
//   ray B at (1.75, 1.5): nodes 0, 2, 3; leaf {4, 5}; hits tri 4 at t = 1 (tri 5 lies behind it, at z = 1.2).
//                                                                         nodes 3, leaves 1, triangles 2
struct HandBvh {
  std::vector<BvhNode> nodes;
  std::vector<BvhTriangle> tris;
  BvhView view() const {
    return {nodes.data(), tris.data(), static_cast<uint32_t>(nodes.size()), static_cast<uint32_t>(tris.size())};
  }
};

BvhNode node(Vec3 lo0, Vec3 hi0, int32_t c0, Vec3 lo1, Vec3 hi1, int32_t c1) {
  BvhNode n{};
  n.lo0 = lo0;
  n.hi0 = hi0;
  n.lo1 = lo1;
  n.hi1 = hi1;
  n.child[0] = c0;
  n.child[1] = c1;
  return n;
}

BvhTriangle triangle_around(float cx, float cy, float z, uint32_t prim) {
  BvhTriangle t{};
  t.v0 = {cx - 0.2f, cy - 0.2f, z};
  t.v1 = {cx + 0.2f, cy - 0.2f, z};
  t.v2 = {cx, cy + 0.2f, z};
  t.prim = prim;
  return t;
}

HandBvh hand_bvh() {
  HandBvh b;
  const float z0 = 0.5f, z1 = 1.5f;
  b.nodes.push_back(node({0, 0, z0}, {1.1f, 2, z1}, 1, {0.9f, 0, z0}, {2, 2, z1}, 2));
  b.nodes.push_back(node({0, 0, z0}, {1.1f, 1, z1}, make_leaf_ref(0, 1), {0, 1, z0}, {1, 2, z1}, make_leaf_ref(1, 1)));
  b.nodes.push_back(node({0.9f, 0, z0}, {2, 1, z1}, make_leaf_ref(2, 1), {1, 1, z0}, {2, 2, z1}, 3));
  b.nodes.push_back(
      node({1, 1, z0}, {1.5f, 2, z1}, make_leaf_ref(3, 1), {1.5f, 1, z0}, {2, 2, z1}, make_leaf_ref(4, 2)));
  b.tris = {triangle_around(0.5f, 0.5f, 1.f, 0),  triangle_around(0.5f, 1.5f, 1.f, 1),
            triangle_around(1.5f, 0.5f, 1.f, 2),  triangle_around(1.25f, 1.5f, 1.f, 3),
            triangle_around(1.75f, 1.5f, 1.f, 4), triangle_around(1.75f, 1.5f, 1.2f, 5)};
  return b;
}

const Ray kRayA{{0.5f, 0.5f, 0.f}, 0.f, {0.f, 0.f, 1.f}, __builtin_huge_valf()};
const Ray kRayB{{1.75f, 1.5f, 0.f}, 0.f, {0.f, 0.f, 1.f}, __builtin_huge_valf()};

// Triangles at byte 4096: tri 0 = [4096, 4144) is one 64-byte line and sectors 128-129; tri 4 = [4288, 4336) is
// line 67, sectors 134-135; tri 5 = [4336, 4384) straddles lines 67-68 and covers sectors 135-136.
SimtConfig hand_config(uint32_t line_bytes = 64) {
  SimtConfig c;
  c.warp_size = 32;
  c.line_bytes = line_bytes;
  c.sector_bytes = 32;
  c.node_base = 0;
  c.tri_base = 4096;
  return c;
}

uint64_t lanes_mask(uint32_t from, uint32_t to) {  // lanes [from, to)
  uint64_t m = 0;
  for (uint32_t l = from; l < to; ++l) m |= uint64_t{1} << l;
  return m;
}

struct WarpRun {
  CoherenceCounters c;
  std::vector<SimtStep> steps;
  std::vector<Hit> hits;
  std::vector<RayCounters> rays;
  WarpTrace trace;
};

WarpRun run_warp(const HandBvh& b, const std::vector<Ray>& rays, const SimtConfig& config) {
  WarpRun r;
  r.hits.resize(rays.size());
  r.rays.resize(rays.size());
  simt_trace_warp(b.view(), rays.data(), static_cast<uint32_t>(rays.size()), config, r.hits.data(), r.c, &r.trace,
                  r.rays.data(), &r.steps);
  return r;
}

void expect_step(const SimtStep& s, SimtStepKind kind, uint64_t active, uint32_t lines, uint32_t sectors) {
  EXPECT_EQ(static_cast<int>(s.kind), static_cast<int>(kind));
  EXPECT_EQ(s.active, active);
  EXPECT_EQ(s.lines, lines);
  EXPECT_EQ(s.sectors, sectors);
}

TEST(SimtWarp, AllLanesOnOnePath) {
  const HandBvh b = hand_bvh();
  const WarpRun r = run_warp(b, std::vector<Ray>(32, kRayA), hand_config());
  const uint64_t all = lanes_mask(0, 32);
  ASSERT_EQ(r.steps.size(), 4u);
  expect_step(r.steps[0], SimtStepKind::Node, all, 1, 2);
  expect_step(r.steps[1], SimtStepKind::Node, all, 1, 2);
  expect_step(r.steps[2], SimtStepKind::Leaf, all, 0, 0);
  expect_step(r.steps[3], SimtStepKind::Triangle, all, 1, 2);
  EXPECT_DOUBLE_EQ(r.c.simt_efficiency(), 1.0);
  EXPECT_DOUBLE_EQ(r.c.triangle_simt_efficiency(), 1.0);
  EXPECT_EQ(r.c.node_lines, r.c.node_steps);
  EXPECT_EQ(r.c.triangle_lines, r.c.triangle_steps);
  EXPECT_EQ(r.c.nodes, 64u);
  for (size_t i = 0; i < 32; ++i) {
    EXPECT_EQ(r.hits[i].prim, 0u);
    EXPECT_EQ(r.hits[i].t, 1.f);
    EXPECT_EQ(r.rays[i].nodes, 2u);
    EXPECT_EQ(r.rays[i].leaves, 1u);
    EXPECT_EQ(r.rays[i].triangles, 1u);
  }
  // The steps for the timing model: node 0's sectors, node 1's, the leaf step (no fetch), then tri 0's.
  EXPECT_EQ(r.trace.sectors, (std::vector<uint32_t>{0, 1, 2, 3, 128, 129}));
  EXPECT_EQ(r.trace.request_end, (std::vector<uint32_t>{2, 4, 4, 6}));
  EXPECT_EQ(r.trace.kinds, (std::vector<SimtStepKind>{SimtStepKind::Node, SimtStepKind::Node, SimtStepKind::Leaf,
                                                      SimtStepKind::Triangle}));
  EXPECT_EQ(r.trace.lanes, 32u);
}

TEST(SimtWarp, DisjointSubtreesAndTheSpeculativeNodeWalk) {
  const HandBvh b = hand_bvh();
  std::vector<Ray> rays(16, kRayA);
  rays.insert(rays.end(), 16, kRayB);
  const WarpRun r = run_warp(b, rays, hand_config());
  const uint64_t all = lanes_mask(0, 32), lanes_b = lanes_mask(16, 32);
  ASSERT_EQ(r.steps.size(), 6u);
  expect_step(r.steps[0], SimtStepKind::Node, all, 1, 2);      // node 0
  expect_step(r.steps[1], SimtStepKind::Node, all, 2, 4);      // nodes 1 and 2: A now holds a leaf, B does not
  expect_step(r.steps[2], SimtStepKind::Node, lanes_b, 1, 2);  // node 3 (A's lanes have no node left)
  expect_step(r.steps[3], SimtStepKind::Leaf, all, 0, 0);
  expect_step(r.steps[4], SimtStepKind::Triangle, all, 2, 4);      // tri 0 and tri 4
  expect_step(r.steps[5], SimtStepKind::Triangle, lanes_b, 2, 2);  // tri 5 straddles two lines
  EXPECT_EQ(r.c.node_steps, 3u);
  EXPECT_EQ(r.c.node_lanes, 80u);
  EXPECT_EQ(r.c.node_lines, 4u);
  EXPECT_EQ(r.c.node_fetches, 8u);
  EXPECT_EQ(r.c.leaf_steps, 1u);
  EXPECT_EQ(r.c.leaf_lanes, 32u);
  EXPECT_EQ(r.c.triangle_steps, 2u);
  EXPECT_EQ(r.c.triangle_lanes, 48u);
  EXPECT_EQ(r.c.triangle_lines, 4u);
  EXPECT_EQ(r.c.triangle_fetches, 6u);
  EXPECT_DOUBLE_EQ(r.c.node_simt_efficiency(), 80.0 / 96.0);
  EXPECT_DOUBLE_EQ(r.c.leaf_simt_efficiency(), 1.0);
  EXPECT_DOUBLE_EQ(r.c.simt_efficiency(), 112.0 / 128.0);
  EXPECT_EQ(r.c.nodes, r.c.node_lanes);
  EXPECT_EQ(r.c.leaves, r.c.leaf_lanes);
  EXPECT_EQ(r.c.triangles, r.c.triangle_lanes);
  for (size_t i = 0; i < 32; ++i) {
    EXPECT_EQ(r.hits[i].prim, i < 16 ? 0u : 4u);
    EXPECT_EQ(r.rays[i].nodes, i < 16 ? 2u : 3u);
    EXPECT_EQ(r.rays[i].triangles, i < 16 ? 1u : 2u);
  }
  // With 128-byte lines nodes 0 and 1 share a line, and so do nodes 2 and 3.
  const WarpRun wide = run_warp(b, rays, hand_config(128));
  EXPECT_EQ(wide.c.node_lines, 4u);
  EXPECT_EQ(wide.steps[1].lines, 2u);
  EXPECT_EQ(wide.c.node_fetches, r.c.node_fetches);
}

TEST(SimtWarp, LanesHoldingALeafKeepWalkingNodes) {
  // Ray W runs along x = 1, inside both halves' boxes, and hits nothing. Alone, it postpones leaf {tri 0}
  // after nodes 0 and 1, tests it, and only then fetches node 2 from its stack. Next to ray B, which holds no
  // leaf after two steps, W fetches node 2 in the third node step while still holding leaf {tri 0}: node 2's
  // child {tri 2} then waits in node_ref and W tests both leaves in two leaf steps.
  const HandBvh b = hand_bvh();
  const Ray w{{1.f, 0.5f, 0.f}, 0.f, {0.f, 0.f, 1.f}, __builtin_huge_valf()};
  const WarpRun alone = run_warp(b, {w}, hand_config());
  ASSERT_EQ(alone.steps.size(), 7u);
  EXPECT_EQ(static_cast<int>(alone.steps[2].kind), static_cast<int>(SimtStepKind::Leaf));  // after 2 nodes
  EXPECT_EQ(static_cast<int>(alone.steps[4].kind), static_cast<int>(SimtStepKind::Node));  // node 2, later
  RayCounters scalar;
  const Hit expect = closest_hit(b.view(), w, scalar);
  EXPECT_FALSE(expect.valid());
  EXPECT_EQ(alone.rays[0].nodes, scalar.nodes);
  EXPECT_EQ(alone.rays[0].leaves, scalar.leaves);

  const WarpRun pair = run_warp(b, {w, kRayB}, hand_config());
  ASSERT_EQ(pair.steps.size(), 8u);
  expect_step(pair.steps[0], SimtStepKind::Node, 0b11, 1, 2);  // node 0
  expect_step(pair.steps[1], SimtStepKind::Node, 0b11, 2, 4);  // W: node 1 (leaf {tri 0}); B: node 2
  expect_step(pair.steps[2], SimtStepKind::Node, 0b11, 2, 4);  // W: node 2, speculatively; B: node 3
  expect_step(pair.steps[3], SimtStepKind::Leaf, 0b11, 0, 0);
  expect_step(pair.steps[4], SimtStepKind::Triangle, 0b11, 2, 4);  // tri 0 and tri 4
  expect_step(pair.steps[5], SimtStepKind::Triangle, 0b10, 2, 2);  // tri 5
  expect_step(pair.steps[6], SimtStepKind::Leaf, 0b01, 0, 0);      // W's postponed leaf {tri 2}
  expect_step(pair.steps[7], SimtStepKind::Triangle, 0b01, 2, 2);  // tri 2 = bytes [96, 144): two lines
  EXPECT_EQ(std::memcmp(&pair.hits[0], &expect, sizeof(Hit)), 0);
  EXPECT_EQ(pair.hits[1].prim, 4u);
}

TEST(SimtWarp, PartiallyActiveAndRejectedLanes) {
  const HandBvh b = hand_bvh();
  std::vector<Ray> rays(10, kRayA);
  rays.insert(rays.end(), 10, kRayB);
  rays[3].org.x = std::nanf("");  // rejected by traversal_begin: never active
  const WarpRun r = run_warp(b, rays, hand_config());
  const uint64_t present = lanes_mask(0, 20) & ~uint64_t{1 << 3};
  ASSERT_EQ(r.steps.size(), 6u);
  expect_step(r.steps[0], SimtStepKind::Node, present, 1, 2);
  expect_step(r.steps[2], SimtStepKind::Node, lanes_mask(10, 20), 1, 2);
  EXPECT_EQ(r.c.rays, 20u);
  EXPECT_EQ(r.c.warps, 1u);
  EXPECT_EQ(r.c.node_lanes, 19u + 19u + 10u);
  EXPECT_DOUBLE_EQ(r.c.node_simt_efficiency(), 48.0 / 96.0);
  EXPECT_DOUBLE_EQ(r.c.leaf_simt_efficiency(), 19.0 / 32.0);
  EXPECT_FALSE(r.hits[3].valid());
  EXPECT_EQ(r.rays[3].nodes, 0u);

  // No lane at all does any work: no steps, no requests.
  const WarpRun none = run_warp(b, std::vector<Ray>(5, rays[3]), hand_config());
  EXPECT_TRUE(none.steps.empty());
  EXPECT_EQ(none.trace.requests(), 0u);
  EXPECT_EQ(none.c.simt_efficiency(), 0.0);
}

}  // namespace
}  // namespace raycoh
