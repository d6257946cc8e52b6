// --shard I/N (harness/shard.h): the N shards of a work list are a partition of it, for any N.
#include "harness/shard.h"

#include <gtest/gtest.h>

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

// Union = the whole list, pairwise disjoint: every unit is owned by exactly one shard, for N = 1 .. 300.
TEST(Shard, TheShardsPartitionTheWorkListForAnyCount) {
  const std::vector<std::string> all = units();
  ASSERT_EQ(std::set<std::string>(all.begin(), all.end()).size(), all.size());
  for (int n = 1; n <= 300; ++n) {
    size_t total = 0;
    std::set<std::string> seen;
    for (int i = 0; i < n; ++i) {
      const Shard shard{i, n};
      for (const std::string& u : all)
        if (shard.owns(u)) {
          ++total;
          EXPECT_TRUE(seen.insert(u).second) << "unit owned twice, n = " << n;
        }
    }
    EXPECT_EQ(total, all.size()) << "n = " << n;
    EXPECT_EQ(seen.size(), all.size()) << "n = " << n;
  }
}

// The owner depends on the unit's name only (any list order, any other units), and small counts spread the work.
TEST(Shard, OwnershipDependsOnTheUnitAloneAndIsSpread) {
  const std::vector<std::string> all = units();  // 210 units
  for (int n : {2, 3, 4, 8}) {
    std::vector<int> per(n, 0);
    for (const std::string& u : all) ++per[Shard::owner(u, n)];
    for (int c : per) EXPECT_GT(c, static_cast<int>(all.size()) / n / 2) << "n = " << n;
  }
  EXPECT_EQ(Shard::owner(experiment_unit("cornell", 3, "ours"), 5), Shard::owner("cornell\x1f"
                                                                                 "3\x1fours",
                                                                                 5));
  EXPECT_TRUE((Shard{0, 1}.owns("anything")));
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
