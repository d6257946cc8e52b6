// --shard I/N (records/shard.h): the N shards of a work list are a partition of it, for any N.
#include "records/shard.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/error.h"
#include "tests/test_util.h"

namespace raycoh::test {
namespace {

std::vector<std::string> units() {
  std::vector<std::string> u;
  for (const char* scene : {"cornell", "voxels", "sibenik"})
    for (int frame = 0; frame < 7; ++frame) {
      u.push_back(experiment_unit(scene, frame, "primary"));
      for (int k : {8, 16, 32, 64}) u.push_back(experiment_unit(scene, frame, "ours:tile=8x8,k=" + std::to_string(k)));
      for (const char* m : {"noopt", "noopt+origin", "ours+reis", "contiguous", "direct"})
        u.push_back(experiment_unit(scene, frame, m));
    }
  return u;
}

// Union = the whole list, pairwise disjoint: every unit has exactly one shard in [0, N), for N = 1 .. 300; shard
// sizes differ by at most one.
TEST(Shard, TheShardsPartitionTheWorkListForAnyCount) {
  const std::vector<std::string> all = units();
  ASSERT_EQ(std::set<std::string>(all.begin(), all.end()).size(), all.size());
  for (int n = 1; n <= 300; ++n) {
    const std::vector<int> owner = deal_units(all, n);
    ASSERT_EQ(owner.size(), all.size());
    std::vector<std::set<std::string>> shards(n);
    for (size_t u = 0; u < all.size(); ++u) {
      ASSERT_GE(owner[u], 0);
      ASSERT_LT(owner[u], n);
      shards[owner[u]].insert(all[u]);
    }
    std::set<std::string> together;
    size_t smallest = all.size(), largest = 0;
    for (const auto& s : shards) {
      for (const std::string& u : s) EXPECT_TRUE(together.insert(u).second) << "in two shards: n = " << n;
      smallest = std::min(smallest, s.size());
      largest = std::max(largest, s.size());
    }
    EXPECT_EQ(together, std::set<std::string>(all.begin(), all.end())) << "n = " << n;
    EXPECT_LE(largest - smallest, 1u) << "n = " << n;
  }
}

// quality and converge: the scene x generator units (owned_units, as QualityRun and ConvergeRun deal them) of N
// shards are a partition of the run's units for N = 1 .. 60, and a whole run owns every unit.
TEST(Shard, QualityAndConvergeShardsPartitionTheSceneGeneratorUnits) {
  std::vector<std::string> all;
  for (const char* scene : {"cornell", "voxels:size=8", "../shared/scenes/sibenik/sibenik.glb"})
    for (const char* g : {"noopt", "ours", "ours:k=8", "tile", "sadeghi", "microjitter", "contiguous"})
      all.push_back(render_unit(scene, g));
  ASSERT_EQ(std::set<std::string>(all.begin(), all.end()).size(), all.size());
  const std::vector<bool> whole = owned_units(all, Shard{});
  EXPECT_EQ(std::count(whole.begin(), whole.end(), true), static_cast<long>(all.size()));
  for (int n = 1; n <= 60; ++n) {
    std::vector<int> owners(all.size(), 0);
    size_t smallest = all.size(), largest = 0;
    for (int i = 0; i < n; ++i) {
      const std::vector<bool> owned = owned_units(all, Shard{i, n});
      ASSERT_EQ(owned.size(), all.size());
      size_t mine = 0;
      for (size_t u = 0; u < all.size(); ++u) {
        owners[u] += owned[u];
        mine += owned[u];
      }
      smallest = std::min(smallest, mine);
      largest = std::max(largest, mine);
    }
    for (size_t u = 0; u < all.size(); ++u) EXPECT_EQ(owners[u], 1) << all[u] << " in n = " << n;
    EXPECT_LE(largest - smallest, 1u) << "n = " << n;
  }
}

// A unit's shard depends on the set of units, not on the order they are listed in.
TEST(Shard, TheDealDoesNotDependOnListOrder) {
  std::vector<std::string> all = units();
  const std::vector<int> owner = deal_units(all, 7);
  std::map<std::string, int> by_name;
  for (size_t u = 0; u < all.size(); ++u) by_name[all[u]] = owner[u];
  std::reverse(all.begin(), all.end());
  const std::vector<int> reversed = deal_units(all, 7);
  for (size_t u = 0; u < all.size(); ++u) EXPECT_EQ(reversed[u], by_name[all[u]]) << all[u];
  EXPECT_EQ(deal_units({"anything"}, 1), std::vector<int>{0});
}

TEST(Shard, ParsesIOfNAndNamesTheValidRange) {
  const Shard s = parse_shard("--shard", "2/4");
  EXPECT_EQ(s.index, 2);
  EXPECT_EQ(s.count, 4);
  EXPECT_EQ(s.text(), "2/4");
  EXPECT_TRUE(parse_shard("--shard", "0/1").whole());
  for (const char* bad : {"4/4", "1/0", "-1/4", "1", "a/b", "1/4/2", "", "/4", "1/", "0/100001"})
    EXPECT_NE(error_of([&] { parse_shard("--shard", bad); }).find("--shard"), std::string::npos) << bad;
  EXPECT_NE(error_of([] { parse_shard("--shard", "4/4"); }).find("I in [0, N)"), std::string::npos);
}

}  // namespace
}  // namespace raycoh::test
