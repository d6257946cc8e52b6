// The compressed 8-wide BVH (core/cwbvh.h, bvh/cwbvh_build.h, core/traverse_cwbvh.h): child boxes decode
// conservatively (random boxes and every node of real scenes), the layout holds every triangle once in leaves of
// 1 to 3, and its closest hits equal the BVH2's (`cpu` vs `cpu:bvh=cwbvh`) on the built-in scenes and every shared
// scene, and the `simt` model's CWBVH hits equal the `cpu` tracer's bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "bvh/cwbvh_build.h"
#include "core/sampling.h"
#include "core/traverse_cwbvh.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "tests/test_util.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

bool contains(Vec3 lo, Vec3 hi, const Bounds& b) {
  return lo.x <= b.lo.x && lo.y <= b.lo.y && lo.z <= b.lo.z && hi.x >= b.hi.x && hi.y >= b.hi.y && hi.z >= b.hi.z;
}

TEST(Cwbvh, QuantizedBoxesContainRandomChildren) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  std::uniform_real_distribution<float> lg(-20.f, 20.f);
  for (int trial = 0; trial < 2000; ++trial) {
    // Parents of any position and size, from tiny to huge, some flat on an axis.
    const float scale = std::exp2(lg(rng));
    const Vec3 origin{(u(rng) - 0.5f) * 1e3f * scale, (u(rng) - 0.5f) * scale, (u(rng) - 0.5f) * 1e-3f};
    Bounds child[kCwbvhWidth];
    Bounds box;
    uint32_t slots = 0;
    for (int s = 0; s < kCwbvhWidth; ++s) {
      if (u(rng) < 0.2f) continue;
      slots |= 1u << s;
      Vec3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)};
      if (trial % 5 == 0) a.y = b.y = 0.5f;  // flat
      child[s].grow(origin + a * scale);
      child[s].grow(origin + b * scale);
      box.grow(child[s]);
    }
    if (slots == 0) continue;
    CwbvhNode node{};
    cwbvh_quantize(node, box, child, slots);
    for (int s = 0; s < kCwbvhWidth; ++s) {
      if (!((slots >> s) & 1u)) continue;
      Vec3 lo, hi;
      cwbvh_child_box(node, s, lo, hi);
      ASSERT_TRUE(contains(lo, hi, child[s])) << "trial " << trial << " slot " << s;
      // Not grossly loose: within one quantisation step (plus rounding) of the true box on every axis.
      for (int a = 0; a < 3; ++a) {
        const float step = cwbvh_scale(node.e[a]);
        EXPECT_LE(child[s].lo[a] - lo[a], 2.f * step + std::fabs(lo[a]) * 1e-6f) << trial;
        EXPECT_LE(hi[a] - child[s].hi[a], 2.f * step + std::fabs(hi[a]) * 1e-6f) << trial;
      }
    }
  }
}

// Checks every node's decoded child boxes against the true bounds of the child's triangles; returns the node's
// true bounds. Also counts the triangles reached.
Bounds check_node(const Cwbvh& bvh, uint32_t index, std::vector<int>& seen, size_t& leaves) {
  const CwbvhNode& n = bvh.nodes[index];
  Bounds all;
  for (int s = 0; s < kCwbvhWidth; ++s) {
    if (cwbvh_slot_is_empty(n, s)) {
      EXPECT_FALSE(cwbvh_slot_is_inner(n, s));
      continue;
    }
    Bounds truth;
    if (cwbvh_slot_is_inner(n, s)) {
      EXPECT_EQ(n.meta[s], cwbvh_inner_meta(s));
      const uint32_t child = cwbvh_child_index(n.child_base, n.imask, static_cast<uint32_t>(s));
      EXPECT_GT(child, index);
      EXPECT_LT(child, bvh.nodes.size());
      truth = check_node(bvh, child, seen, leaves);
    } else {
      const uint32_t count = cwbvh_leaf_count(n.meta[s]), offset = cwbvh_leaf_offset(n.meta[s]);
      EXPECT_GE(count, 1u);
      EXPECT_LE(count, 3u);
      EXPECT_LE(offset + count, 24u);
      ++leaves;
      for (uint32_t t = n.tri_base + offset; t < n.tri_base + offset + count; ++t) {
        const BvhTriangle& tri = bvh.tris[t];
        ++seen[tri.prim];
        truth.grow(tri.v0);
        truth.grow(tri.v1);
        truth.grow(tri.v2);
      }
    }
    Vec3 lo, hi;
    cwbvh_child_box(n, s, lo, hi);
    EXPECT_TRUE(contains(lo, hi, truth)) << "node " << index << " slot " << s;
    all.grow(truth);
  }
  return all;
}

std::vector<std::string> test_scenes() {
  std::vector<std::string> specs = {"cornell", "voxels"};
  for (const auto& file : test::shared_scene_files()) specs.push_back(file.string());
  return specs;
}

std::string scene_test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string stem = std::filesystem::path(info.param).stem().string();
  for (char& c : stem)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return stem;
}

// Camera rays through a 64 x 48 grid and as many incoherent rays: from points inside the scene box towards
// uniform directions.
Vec3 uniform_direction(float u, float v) {
  const float z = 1.f - 2.f * u, r = std::sqrt(std::max(0.f, 1.f - z * z)), phi = 2.f * kPi * v;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

std::vector<Ray> test_rays(const Scene& scene) {
  std::vector<Ray> rays;
  const Camera& cam = scene.camera;
  const Vec3 forward = normalize(cam.target - cam.eye);
  const Vec3 right = normalize(cross(forward, cam.up));
  const Vec3 up = cross(right, forward);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      const float sx = (2.f * (x + 0.5f) / 64.f - 1.f) * 0.6f, sy = (1.f - 2.f * (y + 0.5f) / 48.f) * 0.45f;
      rays.push_back(Ray{cam.eye, 0.f, normalize(forward + right * sx + up * sy), __builtin_huge_valf()});
    }
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  const Vec3 e = scene.bounds.extent();
  for (int i = 0; i < 64 * 48; ++i) {
    const Vec3 o = scene.bounds.lo + Vec3{u(rng), u(rng), u(rng)} * e;
    rays.push_back(Ray{o, 0.f, uniform_direction(u(rng), u(rng)), __builtin_huge_valf()});
  }
  return rays;
}

std::vector<Hit> trace(const std::string& spec, const Scene& scene, const Bvh& bvh, const std::vector<Ray>& rays) {
  auto tracer = make_tracer(parse_plugin_spec(spec), scene, bvh);
  std::vector<Hit> hits(rays.size());
  tracer->trace(rays.data(), rays.size(), hits.data());
  return hits;
}

class CwbvhScene : public ::testing::TestWithParam<std::string> {};

TEST_P(CwbvhScene, LayoutIsCompleteAndConservative) {
  const Scene scene = load_scene(GetParam());
  const Cwbvh bvh = build_cwbvh(scene);
  ASSERT_EQ(bvh.tris.size(), scene.triangle_count());
  std::vector<int> seen(scene.triangle_count(), 0);
  size_t leaves = 0;
  const Bounds root = check_node(bvh, 0, seen, leaves);
  EXPECT_TRUE(bvh.bounds.contains(root));
  for (size_t t = 0; t < seen.size(); ++t) ASSERT_EQ(seen[t], 1) << "triangle " << t;
  EXPECT_EQ(leaves, bvh.stats.leaves);
  EXPECT_LT(bvh.stats.max_depth, size_t{kTraversalStackSize});
  std::printf("[cwbvh] %-22s nodes %zu leaves %zu children/node %.2f depth %zu bytes %zu\n", scene.name.c_str(),
              bvh.stats.nodes, bvh.stats.leaves, bvh.stats.children_per_node, bvh.stats.max_depth, bvh.stats.bytes);
}

TEST_P(CwbvhScene, ClosestHitsEqualBvh2) {
  const Scene scene = load_scene(GetParam());
  const Bvh bvh = build_bvh(scene);
  const std::vector<Ray> rays = test_rays(scene);
  const std::vector<Hit> bvh2 = trace("cpu", scene, bvh, rays);
  const std::vector<Hit> cw = trace("cpu:bvh=cwbvh", scene, bvh, rays);
  size_t hits = 0, ties = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(bvh2[i].valid(), cw[i].valid()) << "ray " << i;
    if (!bvh2[i].valid()) continue;
    ++hits;
    // Same closest distance; a different primitive only at exactly that distance (a shared edge met in another
    // order). The same primitive gives the same hit bit for bit: both layouts run the same triangle test.
    ASSERT_EQ(bvh2[i].t, cw[i].t) << "ray " << i;
    if (bvh2[i].prim != cw[i].prim) {
      ++ties;
      continue;
    }
    ASSERT_EQ(std::memcmp(&bvh2[i], &cw[i], sizeof(Hit)), 0) << "ray " << i;
  }
  EXPECT_GT(hits, rays.size() / 4);
  EXPECT_LE(ties, hits / 100 + 1);
  std::printf("[cwbvh parity] %-22s rays %zu hits %zu ties %zu\n", scene.name.c_str(), rays.size(), hits, ties);
}

INSTANTIATE_TEST_SUITE_P(Scenes, CwbvhScene, ::testing::ValuesIn(test_scenes()), scene_test_name);

// The `simt` model runs the same traversal lane by lane: bit-identical hits (built-in scenes and sibenik, to keep
// the model's cost small), and its per-ray counters agree with its step counters.
TEST(Cwbvh, SimtHitsEqualCpu) {
  std::vector<std::string> specs = {"cornell", "voxels"};
  for (const auto& file : test::shared_scene_files())
    if (file.stem() == "sibenik") specs.push_back(file.string());
  for (const std::string& spec : specs) {
    SCOPED_TRACE(spec);
    const Scene scene = load_scene(spec);
    const Bvh bvh = build_bvh(scene);
    const std::vector<Ray> rays = test_rays(scene);
    const std::vector<Hit> cpu = trace("cpu:bvh=cwbvh", scene, bvh, rays);
    auto simt = make_tracer(parse_plugin_spec("simt:bvh=cwbvh"), scene, bvh);
    std::vector<Hit> hits(rays.size());
    simt->trace(rays.data(), rays.size(), hits.data());
    for (size_t i = 0; i < rays.size(); ++i) ASSERT_EQ(std::memcmp(&cpu[i], &hits[i], sizeof(Hit)), 0) << "ray " << i;
    const CoherenceCounters& c = *simt->last_counters();
    EXPECT_EQ(c.rays, rays.size());
    EXPECT_EQ(c.nodes, c.node_lanes);
    EXPECT_EQ(c.leaves, c.leaf_lanes);
    EXPECT_EQ(c.triangles, c.triangle_lanes);
    EXPECT_GT(c.modeled.ms, 0.0);
    EXPECT_NE(simt->params().find("bvh=cwbvh"), std::string::npos);
  }
}

TEST(Cwbvh, RejectsWideBvh2Leaves) {
  const Scene scene = load_scene("cornell");
  BvhBuildConfig c;
  c.max_leaf_size = 8;
  c.min_leaf_size = 8;
  const Bvh bvh = build_bvh(scene, c);
  EXPECT_NE(test::error_of([&] { collapse_to_cwbvh(bvh); }).find("at most 3"), std::string::npos);
}

TEST(Cwbvh, BadLayoutNameIsAnError) {
  const Scene scene = load_scene("cornell");
  const Bvh bvh = build_bvh(scene);
  const std::string msg = test::error_of([&] { make_tracer(parse_plugin_spec("cpu:bvh=bvh4"), scene, bvh); });
  EXPECT_NE(msg.find("cwbvh"), std::string::npos) << msg;
}

}  // namespace
}  // namespace raycoh
