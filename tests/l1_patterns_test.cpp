// The L1 probe's patterns (bench/l1_patterns.h): each regular family touches the lines, sectors and sector
// positions its name says, and the probe's copy of GPGPU-Sim's bank rule agrees with the model's (simt/warp_trace.h).
#include "bench/l1_patterns.h"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <vector>

#include "simt/warp_trace.h"

namespace raycoh::l1probe {
namespace {

std::map<std::string, Features> by_name() {
  std::map<std::string, Features> out;
  for (const Pattern& p : all_patterns(8, 3)) out[p.name] = features(p);
  return out;
}

TEST(L1Patterns, RegularFamiliesTouchWhatTheirNamesSay) {
  const auto f = by_name();
  EXPECT_EQ(f.at("w4-coalesced").lines, 1u);
  EXPECT_EQ(f.at("w4-coalesced").sectors, 4u);
  EXPECT_EQ(f.at("w4-coalesced").bank_max, 1u);
  EXPECT_EQ(f.at("w16-coalesced").lines, 4u);
  EXPECT_EQ(f.at("w16-coalesced").bytes128, 4u);
  EXPECT_EQ(f.at("w4-broadcast").sectors, 1u);
  for (uint32_t lines : {2u, 5u, 8u, 32u}) {
    const std::string l = "w4-lines" + std::to_string(lines);
    EXPECT_EQ(f.at(l + "-samesector").lines, lines);
    EXPECT_EQ(f.at(l + "-samesector").sectors, lines);
    EXPECT_EQ(f.at(l + "-samesector").bank_max, lines);  // every sector at position 0
    EXPECT_EQ(f.at(l + "-samesector").gpgpusim, lines);
    EXPECT_EQ(f.at(l + "-rotated").sectors, lines);
    EXPECT_EQ(f.at(l + "-rotated").bank_max, (lines + 3) / 4);  // positions 0, 1, 2, 3, 0, ...
    EXPECT_EQ(f.at(l + "-samesector").lines4, (lines + 3) / 4);
  }
  EXPECT_EQ(f.at("w4-lines8-2sectors").sectors, 16u);
  EXPECT_EQ(f.at("w4-lines8-2sectors").bank_max, 8u);
  EXPECT_EQ(f.at("w4-lines8-4sectors").sectors, 32u);
  EXPECT_EQ(f.at("w4-line1-3sectors").sectors, 3u);
  EXPECT_EQ(f.at("w4-line1-3sectors").lines, 1u);
}

TEST(L1Patterns, OffsetsStayInThePageAndAligned) {
  for (const Pattern& p : all_patterns(64, 9)) {
    for (uint32_t off : p.offsets) {
      EXPECT_LT(off + p.width, kPage + 1) << p.name;
      EXPECT_EQ(off % p.width, 0u) << p.name;
    }
  }
}

TEST(L1Patterns, GpgpusimRuleIsTheModelsRule) {
  std::mt19937 rng(5);
  for (int i = 0; i < 500; ++i) {
    std::set<uint32_t> distinct;
    const int n = 1 + static_cast<int>(rng() % 32);
    for (int k = 0; k < n; ++k) distinct.insert(rng() % 128);
    const std::vector<uint32_t> sorted(distinct.begin(), distinct.end());
    const std::vector<uint64_t> wide(sorted.begin(), sorted.end());
    EXPECT_EQ(gpgpusim_cycles(sorted), l1_bank_cycles(wide.data(), static_cast<uint32_t>(wide.size()), 4));
  }
}

}  // namespace
}  // namespace raycoh::l1probe
