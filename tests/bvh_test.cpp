// Tests of build_bvh (bvh/bvh_build.cpp): the structural invariants every tracer relies on, on procedural scenes,
// the built-in scenes and the shared scenes; single-triangle and all-degenerate scenes; determinism across thread
// counts; and the errors for bad configurations and bad geometry.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "core/traverse.h"
#include "scenes/scene.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

// A bare scene of the given triangles (3 vertices each, not shared); build_bvh reads only positions/indices.
Scene triangle_scene(const std::string& name, const std::vector<Vec3>& corners) {
  Scene s;
  s.name = name;
  s.positions = corners;
  s.normals.assign(corners.size(), Vec3{0.f, 0.f, 1.f});
  for (uint32_t i = 0; i < corners.size(); ++i) s.indices.push_back(i);
  s.tri_material.assign(corners.size() / 3, 0);
  s.materials.push_back(Material{});
  for (const Vec3& p : corners) s.bounds.grow(p);
  return s;
}

// n random triangles of size about `size` in the box [offset, offset + extent]^3.
Scene random_soup(size_t n, uint32_t seed, float extent = 10.f, float size = 0.3f, float offset = 0.f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(0.f, extent), d(-size, size);
  std::vector<Vec3> corners;
  for (size_t i = 0; i < n; ++i) {
    const Vec3 c{offset + pos(rng), offset + pos(rng), offset + pos(rng)};
    for (int k = 0; k < 3; ++k) corners.push_back(c + Vec3{d(rng), d(rng), d(rng)});
  }
  return triangle_scene("soup", corners);
}

bool inside(const Bounds& box, Vec3 p) {
  return box.lo.x <= p.x && box.lo.y <= p.y && box.lo.z <= p.z && p.x <= box.hi.x && p.y <= box.hi.y && p.z <= box.hi.z;
}

// Checks every invariant of the layout in core/bvh.h and of BvhStats; reports through gtest.
void expect_valid_bvh(const Scene& scene, const Bvh& bvh) {
  const size_t tri_count = scene.triangle_count();
  ASSERT_FALSE(bvh.nodes.empty());
  ASSERT_EQ(bvh.tris.size(), tri_count);
  std::vector<int> seen(tri_count, 0);
  std::vector<int> node_visits(bvh.nodes.size(), 0);
  size_t leaves = 0, max_depth = 0, bad_boxes = 0, bad_tris = 0;

  struct Item {
    int32_t ref;
    Bounds box;  // the box stored for this node in its parent
    size_t depth;
  };
  Bounds root_box;
  root_box.grow(Bounds{bvh.nodes[0].lo0, bvh.nodes[0].hi0});
  root_box.grow(Bounds{bvh.nodes[0].lo1, bvh.nodes[0].hi1});
  std::vector<Item> stack{{0, root_box, 0}};
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    max_depth = std::max(max_depth, item.depth);
    if (is_leaf_ref(item.ref)) {
      ++leaves;
      const uint32_t first = leaf_first(item.ref), count = leaf_count(item.ref);
      EXPECT_LE(count, static_cast<uint32_t>(bvh.config.max_leaf_size));
      ASSERT_LE(size_t{first} + count, bvh.tris.size());
      for (uint32_t i = first; i < first + count; ++i) {
        const BvhTriangle& t = bvh.tris[i];
        ASSERT_LT(t.prim, tri_count);
        ++seen[t.prim];
        const Vec3 v0 = scene.positions[scene.indices[3 * size_t{t.prim}]];
        const Vec3 v1 = scene.positions[scene.indices[3 * size_t{t.prim} + 1]];
        const Vec3 v2 = scene.positions[scene.indices[3 * size_t{t.prim} + 2]];
        if (std::memcmp(&v0, &t.v0, sizeof(Vec3)) || std::memcmp(&v1, &t.v1, sizeof(Vec3)) ||
            std::memcmp(&v2, &t.v2, sizeof(Vec3)))
          ++bad_tris;
        if (!inside(item.box, t.v0) || !inside(item.box, t.v1) || !inside(item.box, t.v2)) ++bad_boxes;
      }
      continue;
    }
    ASSERT_GE(item.ref, 0);
    ASSERT_LT(static_cast<size_t>(item.ref), bvh.nodes.size());
    ++node_visits[item.ref];
    const BvhNode& n = bvh.nodes[item.ref];
    const Bounds b0{n.lo0, n.hi0}, b1{n.lo1, n.hi1};
    if (!item.box.contains(b0) || !item.box.contains(b1)) ++bad_boxes;
    // Pre-order depth first: an inner child always comes after its parent, child 0 right after it.
    if (!is_leaf_ref(n.child[0])) {
      EXPECT_EQ(n.child[0], item.ref + 1);
    }
    if (!is_leaf_ref(n.child[1])) {
      EXPECT_GT(n.child[1], item.ref);
    }
    stack.push_back({n.child[1], b1, item.depth + 1});
    stack.push_back({n.child[0], b0, item.depth + 1});
  }
  EXPECT_EQ(bad_boxes, 0u) << "child boxes or leaf triangles outside the box stored in the parent";
  EXPECT_EQ(bad_tris, 0u) << "leaf triangles differ from the scene's vertices";
  size_t not_once = 0;
  for (int c : seen) not_once += c != 1;
  EXPECT_EQ(not_once, 0u) << "triangles referenced zero or several times";
  size_t unreachable = 0, shared = 0;
  for (int c : node_visits) {
    unreachable += c == 0;
    shared += c > 1;
  }
  EXPECT_EQ(unreachable, 0u);
  EXPECT_EQ(shared, 0u);
  EXPECT_LT(max_depth, static_cast<size_t>(kTraversalStackSize));

  EXPECT_EQ(bvh.stats.inner_nodes, bvh.nodes.size());
  EXPECT_EQ(bvh.stats.leaves, leaves);
  EXPECT_EQ(bvh.stats.triangles, tri_count);
  EXPECT_EQ(bvh.stats.max_depth, max_depth);
  EXPECT_EQ(bvh.stats.bytes, bvh.nodes.size() * 64 + bvh.tris.size() * 48);
  EXPECT_GE(bvh.stats.sah_cost, bvh.config.traversal_cost);
  EXPECT_GE(bvh.stats.build_seconds, 0.0);
  EXPECT_TRUE(bvh.bounds.contains(root_box) && root_box.contains(bvh.bounds));
}

// Brute-force closest hit (same triangle test) to check that traversal finds what the BVH holds.
Hit brute_force_hit(const Bvh& bvh, const Ray& r) {
  TraversalState s;
  traversal_begin(s, r);
  if (s.node_ref == kSentinel) return s.hit;
  for (const BvhTriangle& t : bvh.tris) intersect_triangle(s.ray, t, s.hit);
  return s.hit;
}

void print_stats(const std::string& name, const Bvh& bvh) {
  const BvhStats& s = bvh.stats;
  std::printf("[bvh] %-24s tris %9zu  inner %9zu  leaves %9zu  depth %2zu  SAH %7.2f  %7.1f MiB  %6.3f s\n",
              name.c_str(), s.triangles, s.inner_nodes, s.leaves, s.max_depth, s.sah_cost,
              static_cast<double>(s.bytes) / (1024.0 * 1024.0), s.build_seconds);
}

TEST(Bvh, RandomSoupInvariants) {
  const Scene scene = random_soup(20000, 1);
  const Bvh bvh = build_bvh(scene);
  expect_valid_bvh(scene, bvh);
  EXPECT_GT(bvh.stats.max_depth, 10u);
}

TEST(Bvh, LeafSizeLimitsAreRespected) {
  const Scene scene = random_soup(5000, 2);
  for (int max_leaf : {1, 2, 8, kMaxLeafSize}) {
    BvhBuildConfig config;
    config.max_leaf_size = max_leaf;
    // Expensive node visits push the SAH towards large leaves, so the limit is what stops them.
    config.traversal_cost = 50.f;
    const Bvh bvh = build_bvh(scene, config);
    SCOPED_TRACE(max_leaf);
    expect_valid_bvh(scene, bvh);
  }
}

TEST(Bvh, FarFromOriginAndTinyScenes) {
  for (const auto& [extent, size, offset] :
       {std::tuple{10.f, 0.3f, 1e6f}, std::tuple{1e-5f, 3e-7f, 0.f}, std::tuple{1e-5f, 3e-7f, -1e-6f}}) {
    const Scene scene = random_soup(3000, 3, extent, size, offset);
    const Bvh bvh = build_bvh(scene);
    expect_valid_bvh(scene, bvh);
  }
}

TEST(Bvh, SingleTriangle) {
  const Scene scene = triangle_scene("one", {{0.f, 0.f, 0.f}, {1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}});
  const Bvh bvh = build_bvh(scene);
  expect_valid_bvh(scene, bvh);
  ASSERT_EQ(bvh.nodes.size(), 1u);
  const BvhNode& root = bvh.nodes[0];
  ASSERT_TRUE(is_leaf_ref(root.child[0]));
  ASSERT_TRUE(is_leaf_ref(root.child[1]));
  EXPECT_EQ(leaf_count(root.child[0]), 1u);
  EXPECT_EQ(leaf_count(root.child[1]), 0u);
  EXPECT_EQ(bvh.stats.leaves, 2u);
  EXPECT_EQ(bvh.stats.max_depth, 1u);
  // The empty leaf has the same box as the real one.
  EXPECT_EQ(std::memcmp(&root.lo0, &root.lo1, sizeof(Vec3)), 0);
  EXPECT_EQ(std::memcmp(&root.hi0, &root.hi1, sizeof(Vec3)), 0);

  const Ray ray{{0.25f, 0.25f, 1.f}, 0.f, {0.f, 0.f, -1.f}, 10.f};
  const Hit hit = closest_hit(bvh.view(), ray);
  ASSERT_TRUE(hit.valid());
  EXPECT_EQ(hit.prim, 0u);
  EXPECT_FLOAT_EQ(hit.t, 1.f);
  EXPECT_FLOAT_EQ(hit.u, 0.25f);
  EXPECT_FLOAT_EQ(hit.v, 0.25f);
}

TEST(Bvh, AllDegenerateTriangles) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> pos(-5.f, 5.f);
  std::vector<Vec3> corners;
  // Points, repeated points and collinear (sliver-to-zero) triangles, including many on one spot so that the
  // binned SAH cannot split by centroid and must fall back to splitting the list.
  for (int i = 0; i < 300; ++i) {
    const Vec3 p{pos(rng), pos(rng), pos(rng)};
    corners.insert(corners.end(), {p, p, p});
  }
  for (int i = 0; i < 300; ++i) {
    const Vec3 p{pos(rng), pos(rng), pos(rng)}, d{pos(rng), pos(rng), pos(rng)};
    corners.insert(corners.end(), {p, p + d, p + d * 2.f});
  }
  for (int i = 0; i < 500; ++i)
    corners.insert(corners.end(), {Vec3{1.f, 2.f, 3.f}, Vec3{1.f, 2.f, 3.f}, Vec3{1.f, 2.f, 3.f}});
  const Scene scene = triangle_scene("degenerate", corners);
  const Bvh bvh = build_bvh(scene);
  expect_valid_bvh(scene, bvh);

  // Zero-area triangles are never hit.
  std::uniform_real_distribution<float> unit(-1.f, 1.f);
  for (int i = 0; i < 2000; ++i) {
    const Ray ray{
        {pos(rng), pos(rng), pos(rng)}, 0.f, normalize(Vec3{unit(rng), unit(rng), unit(rng)}), __builtin_huge_valf()};
    EXPECT_FALSE(closest_hit(bvh.view(), ray).valid());
  }
  // The same point repeated everywhere: a root box of zero area.
  const Scene point = triangle_scene("point", std::vector<Vec3>(3 * 100, Vec3{1.f, 1.f, 1.f}));
  const Bvh point_bvh = build_bvh(point);
  expect_valid_bvh(point, point_bvh);
  EXPECT_TRUE(std::isfinite(point_bvh.stats.sah_cost));
}

TEST(Bvh, TraversalMatchesBruteForce) {
  const Scene scene = random_soup(2000, 5);
  const Bvh bvh = build_bvh(scene);
  std::mt19937 rng(6);
  std::uniform_real_distribution<float> pos(-2.f, 12.f);
  int hits = 0;
  for (int i = 0; i < 3000; ++i) {
    // Aimed at a random triangle's first corner, so that most rays hit something.
    const Vec3 org{pos(rng), pos(rng), pos(rng)};
    const Vec3 target = bvh.tris[static_cast<size_t>(rng()) % bvh.tris.size()].v0;
    const Ray ray{org, 0.f, normalize(target - org), __builtin_huge_valf()};
    const Hit a = closest_hit(bvh.view(), ray), b = brute_force_hit(bvh, ray);
    ASSERT_EQ(a.prim, b.prim) << "ray " << i;
    ASSERT_EQ(a.t, b.t) << "ray " << i;
    hits += a.valid();
  }
  EXPECT_GT(hits, 1000);
}

// The tuned kernel's form of the traversal (WideFetch: records read as 16-byte words, the stack apart from the
// state) against the classic one, and the wide record reads against the structs: the same hits, bit for bit.
TEST(Bvh, WideFetchTraversalEqualsClassic) {
  const Scene scene = random_soup(3000, 11);
  const Bvh bvh = build_bvh(scene);
  for (uint32_t i = 0; i < bvh.nodes.size(); ++i) {
    const BvhNode n = load_node_wide(bvh.nodes.data(), i);
    ASSERT_EQ(std::memcmp(&n, &bvh.nodes[i], offsetof(BvhNode, pad)), 0) << "node " << i;
  }
  for (uint32_t i = 0; i < bvh.tris.size(); ++i) {
    const BvhTriangle t = load_triangle_wide(bvh.tris.data(), i);
    const BvhTriangle& want = bvh.tris[i];
    ASSERT_TRUE(std::memcmp(&t.v0, &want.v0, 16) == 0 && std::memcmp(&t.v1, &want.v1, 12) == 0 &&
                std::memcmp(&t.v2, &want.v2, 12) == 0)
        << "triangle " << i;
  }
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> pos(-2.f, 12.f), dir(-1.f, 1.f);
  int hits = 0;
  for (int i = 0; i < 4000; ++i) {
    const Ray ray{{pos(rng), pos(rng), pos(rng)}, 0.f, normalize(Vec3{dir(rng), dir(rng), dir(rng)}), 1e30f};
    RayCounters ca, cb;
    const Hit a = closest_hit(bvh.view(), ray, ca);
    const Hit b = closest_hit<RayCounters, NoAlphaTest, WideFetch>(bvh.view(), ray, cb);
    ASSERT_TRUE(a.prim == b.prim && a.t == b.t && a.u == b.u && a.v == b.v) << "ray " << i;
    ASSERT_TRUE(ca.nodes == cb.nodes && ca.leaves == cb.leaves && ca.triangles == cb.triangles) << "ray " << i;
    hits += a.valid();
  }
  EXPECT_GT(hits, 500);
}

TEST(Bvh, DeterministicAcrossThreadCounts) {
  const Scene scene = random_soup(60000, 7);
  auto build_with = [&](size_t threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return build_bvh(scene);
  };
  const Bvh one = build_with(1), two = build_with(2);
  ASSERT_EQ(one.nodes.size(), two.nodes.size());
  ASSERT_EQ(one.tris.size(), two.tris.size());
  EXPECT_EQ(std::memcmp(one.nodes.data(), two.nodes.data(), one.nodes.size() * sizeof(BvhNode)), 0);
  EXPECT_EQ(std::memcmp(one.tris.data(), two.tris.data(), one.tris.size() * sizeof(BvhTriangle)), 0);
  EXPECT_EQ(one.stats.sah_cost, two.stats.sah_cost);
}

TEST(Bvh, BadConfigurationsAreUserErrors) {
  const Scene scene = random_soup(100, 8);
  auto build_with = [&](auto change) {
    BvhBuildConfig config;
    change(config);
    return build_bvh(scene, config);
  };
  EXPECT_THROW(build_with([](BvhBuildConfig& c) { c.max_leaf_size = 0; }), Error);
  EXPECT_THROW(build_with([](BvhBuildConfig& c) { c.max_leaf_size = kMaxLeafSize + 1; }), Error);
  EXPECT_THROW(build_with([](BvhBuildConfig& c) { c.max_leaf_size = -3; }), Error);
  EXPECT_THROW(build_with([](BvhBuildConfig& c) { c.min_leaf_size = 0; }), Error);
  EXPECT_THROW(build_with([](BvhBuildConfig& c) { c.min_leaf_size = 5; }), Error);
  EXPECT_THROW(build_with([](BvhBuildConfig& c) { c.traversal_cost = 0.f; }), Error);
  EXPECT_THROW(build_with([](BvhBuildConfig& c) { c.intersection_cost = std::nanf(""); }), Error);
  try {
    build_with([](BvhBuildConfig& c) { c.max_leaf_size = 32; });
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("max_leaf_size=32"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("[1, 31]"), std::string::npos) << e.what();
  }
}

TEST(Bvh, BadGeometryIsAUserError) {
  Scene empty = triangle_scene("empty", {});
  EXPECT_THROW(build_bvh(empty), Error);
  Scene out_of_range = random_soup(10, 9);
  out_of_range.indices[7] = 1000;
  EXPECT_THROW(build_bvh(out_of_range), Error);
  Scene nan = random_soup(10, 9);
  nan.positions[4].y = std::nanf("");
  EXPECT_THROW(build_bvh(nan), Error);
}

TEST(Bvh, BuiltinScenes) {
  for (const char* spec : {"cornell", "voxels"}) {
    const Scene scene = load_scene(spec);
    const Bvh bvh = build_bvh(scene);
    SCOPED_TRACE(spec);
    expect_valid_bvh(scene, bvh);
    print_stats(scene.name, bvh);
  }
}

TEST(Bvh, SharedScenes) {
  const auto files = test::shared_scene_files();
  if (files.empty()) GTEST_SKIP() << "no shared scenes found (set RAYCOH_SCENES)";
  for (const auto& file : files) {
    const Scene scene = load_scene(file.string());
    const Bvh bvh = build_bvh(scene);
    SCOPED_TRACE(file.string());
    expect_valid_bvh(scene, bvh);
    print_stats(scene.name, bvh);
    RecordProperty(scene.name + "_sah", std::to_string(bvh.stats.sah_cost));
  }
}

}  // namespace
}  // namespace raycoh
