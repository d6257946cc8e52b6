// The lane address patterns of the L1 probe (bench/l1_probe.cu) and what each candidate wavefront rule predicts
// for them. Host only, header only (tests/l1_patterns_test.cpp checks the features).
//
// A pattern is one warp-wide global load: lane i reads `width` bytes at byte offset offsets[i] of a 4 KB page (32
// lines of 128 bytes, each 4 sectors of 32 bytes). The probe measures, per pattern, the L1's cycles per load
// instruction (clock64) and, under Nsight Compute, its data-stage wavefronts per request; the rules below are the
// hypotheses the measurement decides between:
//   lines4   the simt model's hardware rule: max(1, ceil(distinct lines / 4)) (simt/timed_replay.cpp)
//   lines    one wavefront per distinct 128-byte line
//   sectors4 ceil(distinct sectors / 4)
//   banks    the most distinct sectors that share a sector position (sector mod 4: the 8 of the 32 four-byte data
//            banks that position occupies), i.e. a data-bank conflict degree at sector granularity
//   gpgpusim GPGPU-Sim's rule (l1_bank_cycles, simt/warp_trace.h: 4 sectors a cycle from the highest address, the
//            cycle ends at the first repeated bank)
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "simt/warp_trace.h"

namespace raycoh::l1probe {

using raycoh::l1_bank_cycles;

inline constexpr uint32_t kLine = 128, kSector = 32, kPage = 4096, kLanes = 32;
inline constexpr uint32_t kSpan = 65536;  // the span patterns' range: address bits 7-15 of their lines vary

struct Pattern {
  std::string name;
  uint32_t width = 4;  // bytes per lane: 4, 8 or 16
  std::array<uint32_t, kLanes> offsets{};
};

struct Features {
  uint32_t lines = 0, sectors = 0, bank_max = 0, gpgpusim = 0, lines4 = 0, sectors4 = 0, bytes128 = 0;
};

inline Features features(const Pattern& p) {
  std::set<uint32_t> lines, sectors;
  for (uint32_t off : p.offsets) {
    for (uint32_t b = off; b < off + p.width; b += 4) {  // a lane's bytes stay in one sector (aligned, width <= 16)
      lines.insert(b / kLine);
      sectors.insert(b / kSector);
    }
  }
  Features f;
  f.lines = static_cast<uint32_t>(lines.size());
  f.sectors = static_cast<uint32_t>(sectors.size());
  std::array<uint32_t, 4> per_position{};
  for (uint32_t s : sectors) ++per_position[s % 4];
  f.bank_max = *std::max_element(per_position.begin(), per_position.end());
  const std::vector<uint64_t> sorted(sectors.begin(), sectors.end());
  f.gpgpusim = l1_bank_cycles(sorted.data(), static_cast<uint32_t>(sorted.size()), 4);
  f.lines4 = std::max(1u, (f.lines + 3) / 4);
  f.sectors4 = (f.sectors + 3) / 4;
  f.bytes128 = (p.width * kLanes + kLine - 1) / kLine;
  return f;
}

// Lanes spread round robin over `lines` lines (line j at page line j * stride); in line j a lane reads sector
// (first + j * rotate + lane's turn in its line * sectors_step) mod 4.
inline Pattern spread(std::string name, uint32_t width, uint32_t lines, uint32_t rotate, uint32_t sectors_per_line) {
  Pattern p{std::move(name), width, {}};
  const uint32_t stride = std::max(1u, 32u / lines);
  for (uint32_t lane = 0; lane < kLanes; ++lane) {
    const uint32_t j = lane % lines, turn = lane / lines;
    const uint32_t sector = (j * rotate + turn % sectors_per_line) % 4;
    p.offsets[lane] = (j * stride) * kLine + sector * kSector + (turn / sectors_per_line * width) % kSector;
  }
  return p;
}

// Every pattern of one run: the regular families, then `random_count` node-like patterns (lanes at random 64-byte
// nodes of the page, all reading the same field, as a traversal's node load does).
inline std::vector<Pattern> all_patterns(uint32_t random_count, uint32_t seed) {
  std::vector<Pattern> out;
  for (uint32_t width : {4u, 8u, 16u}) {
    const std::string w = "w" + std::to_string(width);
    Pattern coalesced{w + "-coalesced", width, {}};
    for (uint32_t lane = 0; lane < kLanes; ++lane) coalesced.offsets[lane] = lane * width;
    out.push_back(coalesced);
    out.push_back(Pattern{w + "-broadcast", width, {}});
    for (uint32_t lines : {2u, 3u, 4u, 5u, 6u, 8u, 12u, 16u, 24u, 32u}) {
      const std::string l = w + "-lines" + std::to_string(lines);
      out.push_back(spread(l + "-samesector", width, lines, 0, 1));
      out.push_back(spread(l + "-rotated", width, lines, 1, 1));
      if (lines <= 16) out.push_back(spread(l + "-2sectors", width, lines, 0, 2));
      if (lines <= 8) out.push_back(spread(l + "-4sectors", width, lines, 0, 4));
    }
    for (uint32_t s = 2; s <= 4; ++s)
      out.push_back(spread(w + "-line1-" + std::to_string(s) + "sectors", width, 1, 0, s));
  }
  std::mt19937 rng(seed);
  for (uint32_t i = 0; i < random_count; ++i) {
    const uint32_t nodes = 1 + rng() % 32, field = (rng() % 16) * 4;  // one of a 64-byte node's 4-byte words
    std::vector<uint32_t> pool(nodes);
    for (uint32_t& n : pool) n = rng() % (kPage / 64);
    Pattern p{"w4-node" + std::to_string(nodes) + "-" + std::to_string(i), 4, {}};
    for (uint32_t lane = 0; lane < kLanes; ++lane) p.offsets[lane] = pool[rng() % nodes] * 64 + field;
    out.push_back(p);
  }
  return out;
}

// `count` patterns whose lanes read 2-16 random lines of a 64 KB span (the tag stage's hash beyond bits 7-11),
// each line at its own 4-byte bank (line i of the pattern at word i) so that the data stage takes one wavefront
// and the tag stage alone sets the time. 4-byte lanes; the probe runs them with the 8 loads of a trip at the same
// addresses (the span is the whole footprint).
inline std::vector<Pattern> span_patterns(uint32_t count, uint32_t seed) {
  std::vector<Pattern> out;
  std::mt19937 rng(seed);
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t lines = 2 + rng() % 15;
    std::set<uint32_t> pool;
    while (pool.size() < lines) pool.insert(rng() % (kSpan / kLine));
    const std::vector<uint32_t> picked(pool.begin(), pool.end());
    Pattern p{"w4-span" + std::to_string(lines) + "-" + std::to_string(i), 4, {}};
    for (uint32_t lane = 0; lane < kLanes; ++lane) {
      const uint32_t slot = lane % lines;
      p.offsets[lane] = picked[slot] * kLine + (slot * 4) % kLine;
    }
    out.push_back(p);
  }
  return out;
}

}  // namespace raycoh::l1probe
