// The L1 probe's patterns (bench/l1_patterns.h): each regular family touches the lines, sectors and sector
// positions its name says.
// The model's H100 rule (hopper_l1_stages) against what the probe measured on an H100 for every pattern
// (results/gpu/h100-9566ba3/l1-measured.csv: Nsight Compute's data- and tag-stage wavefronts, clock64 cycles).
#include "bench/l1_patterns.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
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

TEST(L1Patterns, SpanPatternsAreBankFreeAndInTheirSpan) {
  for (const Pattern& p : span_patterns(40, 2)) {
    std::vector<uint64_t> addr(p.offsets.begin(), p.offsets.end());
    for (uint64_t a : addr) EXPECT_LT(a, kSpan) << p.name;
    EXPECT_EQ(hopper_l1_stages(addr.data(), 32, 4).data, 1u) << p.name;  // the tag stage alone sets the time
    EXPECT_GE(features(p).lines, 2u);
  }
}

struct Measured {
  std::string pattern;
  uint32_t width = 0;
  double cycles = 0, data = 0, tag = -1;  // tag < 0: not measured (the tag counter ran on 4-byte patterns only)
  std::vector<uint64_t> offsets;
};

std::vector<Measured> read_measured() {
  const std::string path = std::string(RAYCOH_SOURCE_DIR) + "/results/gpu/h100-9566ba3/l1-measured.csv";
  std::ifstream in(path);
  std::vector<Measured> out;
  std::string line;
  std::getline(in, line);  // header: pattern,width,cycles_per_load,data_wavefronts,tag_wavefronts,offsets
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string field[6];
    for (auto& f : field) std::getline(row, f, ',');
    Measured m{field[0], static_cast<uint32_t>(std::stoul(field[1])), std::stod(field[2]), std::stod(field[3])};
    if (!field[4].empty()) m.tag = std::stod(field[4]);
    std::stringstream offsets(field[5]);
    for (uint64_t o; offsets >> o;) m.offsets.push_back(o);
    out.push_back(m);
  }
  return out;
}

TEST(HopperL1Rule, GivesEveryWavefrontCountMeasuredOnTheH100) {
  const std::vector<Measured> rows = read_measured();
  ASSERT_EQ(rows.size(), 261u) << "results/gpu/h100-9566ba3/l1-measured.csv";
  int tags = 0;
  for (const Measured& m : rows) {
    ASSERT_EQ(m.offsets.size(), 32u) << m.pattern;
    const HopperL1Stages s = hopper_l1_stages(m.offsets.data(), 32, m.width);
    EXPECT_EQ(s.data, std::lround(m.data)) << m.pattern << ": data-stage wavefronts";
    if (m.tag >= 0) {
      EXPECT_EQ(s.tag, std::lround(m.tag)) << m.pattern << ": tag-stage wavefronts";
      ++tags;
    }
    // the timed cycles per load: the slower stage (one wavefront a cycle)
    EXPECT_EQ(hopper_l1_cycles(m.offsets.data(), 32, m.width), std::lround(m.cycles)) << m.pattern;
  }
  EXPECT_EQ(tags, 183);
}

}  // namespace
}  // namespace raycoh::l1probe
