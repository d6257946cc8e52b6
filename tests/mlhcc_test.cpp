// MLHCC: the cuts and codes of a hand-built BVH, and the cut table and keys on a real BVH against a recursive
// reference of the cut rule written independently of the stack-based builder.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "encoders/encoder.h"
#include "encoders/mlhcc_cuts.h"
#include "scenes/scene.h"
#include "tests/encoder_test_util.h"
#include "tests/key_reference.h"

namespace raycoh {
namespace {

using test::keys_of;
using test::kNaN;
using test::kUnitBox;
using test::make_batch;
using test::random_rays;
using test::ray;
using test::ref_end_point;
using test::RefBits;
using test::tiny_bvh;

TEST(Mlhcc, CutsOfAHandBuiltTree) {
  const Bvh bvh = tiny_bvh();
  // lambda = 0.125: no inner node is small enough, so the one level is the four leaves (2 bits).
  const MlhccCutTable fine = build_mlhcc_cuts(bvh, 0.125f, MlhccRanks::Compressed);
  EXPECT_EQ(fine.level_bits, (std::vector<uint32_t>{2}));
  EXPECT_EQ(fine.level_sizes, (std::vector<uint32_t>{4}));
  EXPECT_EQ(fine.cuts[1].rank[1], 1u);
  EXPECT_EQ(fine.cuts[2].rank[0], 2u);
  EXPECT_EQ(fine.summary(), "levels=1 bits=2 nodes=4");
  // lambda = 0.7: nodes 1 and 2 (2 <= 2.1) form level 1, the leaves level 2 (two per parent: 1 bit each) ...
  const MlhccCutTable coarse = build_mlhcc_cuts(bvh, 0.7f, MlhccRanks::Compressed);
  EXPECT_EQ(coarse.level_bits, (std::vector<uint32_t>{1, 1}));
  EXPECT_EQ(coarse.level_sizes, (std::vector<uint32_t>{2, 4}));
  // ... and numbered within the whole level, 2 bits.
  const MlhccCutTable global = build_mlhcc_cuts(bvh, 0.7f, MlhccRanks::Global);
  EXPECT_EQ(global.level_bits, (std::vector<uint32_t>{1, 2}));
  EXPECT_EQ(global.cuts[2].rank[1], 3u);
}

TEST(Mlhcc, HandComputedCodes) {
  const Bvh bvh = tiny_bvh();
  const EncoderContext ctx{kUnitBox, &bvh};
  // Origin in leaf 2; end point o + 0.25 x (1,0,0) = (0.85, .5, .5) in leaf 3.
  const RayBatch batch = make_batch({ray({0.6f, 0.5f, 0.5f}, {1, 0, 0}),
                                     ray({0.5f, 0.5f, 0.5f}, {0, 1, 0}),    // on the shared face: child 0
                                     ray({2.f, 0.5f, 0.5f}, {1, 0, 0}),     // outside: clamped into leaf 3
                                     ray({kNaN, 0.5f, 0.5f}, {1, 0, 0})});  // NaN: box's low face, leaf 0
  const auto fine = keys_of("mlhcc:bits=64", ctx, batch);
  EXPECT_EQ(fine[0], 0xB000000000000000ull);  // 10 11
  EXPECT_EQ(fine[1], 0x5000000000000000ull);  // 01 01 (y moves inside leaf 1)
  EXPECT_EQ(fine[2], 0xF000000000000000ull);  // 11 11
  // NaN x: origin at x = 0 (leaf 0); end point (NaN) likewise.
  EXPECT_EQ(fine[3], 0x0000000000000000ull);
  EXPECT_EQ(keys_of("mlhcc", ctx, batch)[0], 0xB0000000ull);
  EXPECT_EQ(keys_of("mlhcc:points=origin,bits=64", ctx, batch)[0], 0x8000000000000000ull);  // 10
  EXPECT_EQ(keys_of("mlhcc:lambda=0.7,bits=64", ctx, batch)[0], 0xD000000000000000ull);     // 1 1 | 0 1
  EXPECT_EQ(keys_of("mlhcc:lambda=0.7,ranks=global,bits=64", ctx, batch)[0],
            0xEC00000000000000ull);                                               // 1 1 | 10 11
  EXPECT_EQ(keys_of("mlhcc:L=0,bits=64", ctx, batch)[0], 0xA000000000000000ull);  // end = origin: 10 10
}

// A recursive reference of the cut rule, written independently of the stack-based builder.
struct RefMlhcc {
  const Bvh& bvh;
  float lambda;
  bool global;
  std::map<std::pair<uint32_t, int>, std::pair<uint32_t, uint32_t>> cut;  // (node, slot) -> (level, rank)
  std::vector<uint32_t> widths, sizes;

  static float area(Vec3 lo, Vec3 hi) { return Bounds{lo, hi}.half_area(); }
  float child_area(uint32_t node, int slot) const {
    const BvhNode& n = bvh.nodes[node];
    return slot == 0 ? area(n.lo0, n.hi0) : area(n.lo1, n.hi1);
  }
  static uint32_t bits_for(size_t n) {
    uint32_t w = 0;
    while ((size_t{1} << w) < n) ++w;
    return w;
  }
  // The cut nodes directly beneath a cut node (the children of `node` are its first candidates), DFS order.
  void cut_children(uint32_t node, float parent_area, std::vector<std::pair<uint32_t, int>>& out) const {
    for (int slot = 0; slot < 2; ++slot) {
      const int32_t ref = bvh.nodes[node].child[slot];
      if (is_leaf_ref(ref) || child_area(node, slot) <= lambda * parent_area)
        out.push_back({node, slot});
      else
        cut_children(static_cast<uint32_t>(ref), parent_area, out);
    }
  }
  void build(uint32_t node, float node_area, uint32_t level) {
    std::vector<std::pair<uint32_t, int>> children;
    cut_children(node, node_area, children);
    if (sizes.size() <= level) {
      sizes.resize(level + 1, 0);
      widths.resize(level + 1, 0);
    }
    for (const auto& c : children) cut[c] = {level + 1, global ? sizes[level]++ : 0};
    if (!global) {
      for (uint32_t i = 0; i < children.size(); ++i) cut[children[i]].second = i;
      sizes[level] += static_cast<uint32_t>(children.size());
      widths[level] = std::max(widths[level], bits_for(children.size()));
    }
    for (const auto& c : children) {
      const int32_t ref = bvh.nodes[c.first].child[c.second];
      if (!is_leaf_ref(ref)) build(static_cast<uint32_t>(ref), child_area(c.first, c.second), level + 1);
    }
  }
  RefMlhcc(const Bvh& b, float l, bool g) : bvh(b), lambda(l), global(g) {
    const BvhNode& root = bvh.nodes[0];
    Bounds box{root.lo0, root.hi0};
    box.grow(Bounds{root.lo1, root.hi1});
    build(0, box.half_area(), 0);
    if (global)
      for (size_t l = 0; l < sizes.size(); ++l) widths[l] = bits_for(sizes[l]);
  }
  // Rank per level (index level - 1) of the cut nodes on p's descent; missing levels are 0.
  std::vector<uint32_t> path_ranks(Vec3 p) const {
    std::vector<uint32_t> ranks(widths.size(), 0);
    uint32_t node = 0;
    for (;;) {
      const BvhNode& n = bvh.nodes[node];
      auto dist = [&](Vec3 lo, Vec3 hi) {
        float s = 0.f;
        for (int a = 0; a < 3; ++a) {
          const float d = std::max({lo[a] - p[a], p[a] - hi[a], 0.f});
          s = s + d * d;
        }
        return s;
      };
      const float d0 = dist(n.lo0, n.hi0), d1 = dist(n.lo1, n.hi1);
      const int slot = d0 < d1 ? 0 : d1 < d0 ? 1 : (area(n.lo1, n.hi1) < area(n.lo0, n.hi0) ? 1 : 0);
      auto it = cut.find({node, slot});
      if (it != cut.end()) ranks[it->second.first - 1] = it->second.second;
      if (is_leaf_ref(n.child[slot])) return ranks;
      node = static_cast<uint32_t>(n.child[slot]);
    }
  }
  uint64_t code(const Ray& r, const Bounds& box, float factor) const {
    auto clamp = [&](Vec3 p) {
      return Vec3{std::clamp(p.x, box.lo.x, box.hi.x), std::clamp(p.y, box.lo.y, box.hi.y),
                  std::clamp(p.z, box.lo.z, box.hi.z)};
    };
    const auto a = path_ranks(clamp(r.org));
    const auto b = path_ranks(clamp(ref_end_point(r.org, r.dir, r.tmax, box, factor)));
    RefBits bits;
    for (size_t l = 0; l < widths.size(); ++l) {
      bits.push(a[l], static_cast<int>(widths[l]));
      bits.push(b[l], static_cast<int>(widths[l]));
    }
    return bits.code();
  }
};

TEST(Mlhcc, MatchesTheRecursiveReferenceOnARealBvh) {
  const Scene scene = load_scene("voxels");
  const Bvh bvh = build_bvh(scene);
  const EncoderContext ctx{scene.bounds, &bvh};
  const RayBatch batch = make_batch(random_rays(scene.bounds, 4000, 5));
  for (const auto& [lambda, global] :
       std::vector<std::pair<float, bool>>{{0.125f, false}, {0.3f, false}, {0.125f, true}, {0.02f, false}}) {
    const RefMlhcc ref(bvh, lambda, global);
    const MlhccCutTable table = build_mlhcc_cuts(bvh, lambda, global ? MlhccRanks::Global : MlhccRanks::Compressed);
    ASSERT_EQ(table.level_bits, ref.widths) << lambda;
    ASSERT_EQ(table.level_sizes, ref.sizes) << lambda;
    const std::string spec = fmt::format("mlhcc:lambda={},ranks={}", lambda, global ? "global" : "compressed");
    const auto k64 = keys_of(spec + ",bits=64", ctx, batch);
    const auto k32 = keys_of(spec, ctx, batch);
    size_t distinct = 0;
    for (size_t i = 0; i < batch.size(); ++i) {
      const uint64_t expected = ref.code(batch.rays[i], scene.bounds, 0.25f);
      ASSERT_EQ(k64[i], expected) << spec << " ray " << i;
      ASSERT_EQ(k32[i], expected >> 32) << spec << " ray " << i;
      distinct += i > 0 && k64[i] != k64[i - 1];
    }
    EXPECT_GT(distinct, batch.size() / 2) << spec;  // the codes discriminate
  }
}

TEST(Mlhcc, NeedsTheBvh) {
  EXPECT_THROW(make_encoder(parse_plugin_spec("mlhcc"), EncoderContext{kUnitBox, nullptr}), Error);
}

}  // namespace
}  // namespace raycoh
