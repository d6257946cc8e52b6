// What the warp model (simt/simt.h) hands to the timing model (simt/timed_replay.h): one warp's steps in issue
// order, each with its kind and the sectors it requests. Host only.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace raycoh {

enum class SimtStepKind : uint8_t { Node, Leaf, Triangle };

// A node or triangle record is read as consecutive 16-byte words (BVH2 node 4, triangle 3, CWBVH node 5).
constexpr uint32_t kMaxRecordWords = 5;

// Cycles of GPGPU-Sim's L1 for one load instruction that requests `count` distinct sectors (sorted ascending):
// ldst_unit::process_memory_access_queue_l1cache (src/gpgpu-sim/shader.cc, GPGPU-Sim 4.2) takes the instruction's
// accesses, one per 32-byte sector (warp_inst_t::memory_coalescing_arch, coalescing arch >= 40), from the back of
// its queue (the highest address first), up to `banks` in a cycle, and stops the cycle at the first access whose
// bank (l1d_cache_config::set_bank: sector number mod banks, 32-byte interleaving, linear) is already taken.
inline uint32_t l1_bank_cycles(const uint64_t* sectors, uint32_t count, uint32_t banks) {
  uint32_t cycles = 0, taken = 0, in_cycle = 0;
  for (uint32_t i = count; i-- > 0;) {
    const uint32_t bank = 1u << (sectors[i] % banks);
    if (in_cycle == 0 || (taken & bank) || in_cycle == banks) {
      ++cycles;
      taken = 0;
      in_cycle = 0;
    }
    taken |= bank;
    ++in_cycle;
  }
  return cycles;
}

// Cycles of an H100's L1 for one warp load of `width` (4, 8 or 16) bytes per lane at the lanes' byte addresses
// addr[0..n) (lane order; only active lanes), as measured with bench/l1_probe.cu on L1 hits (results/gpu/
// h100-9566ba3/README.md: this rule gives Nsight Compute's data-stage wavefronts of all 261 probed patterns and its
// tag-stage wavefronts of all 183 probed 4-byte patterns):
// - data stage: the warp in passes of 128 / width lanes (32, 16 or 8); a pass takes as many wavefronts as the most
//   distinct 4-byte words that fall in one of the 32 four-byte banks (word address mod 32), at least one;
// - tag stage: as many wavefronts as the most distinct 128-byte lines that fall in one of 4 tag banks, the bank of
//   line k (address bits 7-15) being (parity(k & 0x16F), parity(k & 0x0B5)): the only linear hash of those bits
//   that fits every count (results/gpu/h100-9566ba3/README.md); bits from 16 up were not probed and are left out;
// - the load: the larger of the two, one wavefront a cycle.
struct HopperL1Stages {
  uint32_t data = 0, tag = 0;
};
inline HopperL1Stages hopper_l1_stages(const uint64_t* addr, uint32_t n, uint32_t width) {
  const uint32_t pass = width >= 4 && width <= 16 ? 128 / width : 32, words_per_lane = std::max(1u, width / 4);
  uint32_t data = 0;
  uint64_t words[32 * 4], lines[64];
  uint32_t line_count = 0;
  for (uint32_t first = 0; first < n; first += pass) {
    uint32_t count = 0;
    for (uint32_t l = first; l < n && l < first + pass; ++l)
      for (uint32_t w = 0; w < words_per_lane; ++w) words[count++] = addr[l] / 4 + w;
    std::sort(words, words + count);
    count = static_cast<uint32_t>(std::unique(words, words + count) - words);
    uint32_t per_bank[32] = {}, most = 1;
    for (uint32_t i = 0; i < count; ++i) most = std::max(most, ++per_bank[words[i] % 32]);
    data += most;
  }
  for (uint32_t l = 0; l < n && l < 64; ++l) lines[line_count++] = addr[l] / 128;
  std::sort(lines, lines + line_count);
  line_count = static_cast<uint32_t>(std::unique(lines, lines + line_count) - lines);
  uint32_t per_tag_bank[4] = {}, tag = 1;
  for (uint32_t i = 0; i < line_count; ++i) {
    const uint64_t k = lines[i];
    const uint32_t bank = (__builtin_popcountll(k & 0x16Fu) & 1u) | (__builtin_popcountll(k & 0x0B5u) & 1u) << 1;
    tag = std::max(tag, ++per_tag_bank[bank]);
  }
  return {data, tag};
}
inline uint32_t hopper_l1_cycles(const uint64_t* addr, uint32_t n, uint32_t width) {
  const HopperL1Stages s = hopper_l1_stages(addr, n, width);
  return std::max(s.data, s.tag);
}

// Step r requests sectors[begin(r), request_end[r]), begin(0) = 0 and begin(r) = request_end[r - 1]; kinds[r] is
// its kind (leaf steps request nothing: the leaf reference came with its parent node). Sector numbers are byte
// address / sector_bytes. `lanes` is the number of rays the warp holds (the last warp of a batch may hold fewer).
// With `l1_banks` > 0 (set before tracing), word_cycles[r][w] holds l1_bank_cycles of the sectors that the lanes'
// 16-byte word w of the step's record lies in; with `l1_words`, hopper_l1_cycles of a 4-byte load of that word (0
// beyond the record and for leaf steps).
struct WarpTrace {
  std::vector<uint32_t> sectors;
  std::vector<uint32_t> request_end;
  std::vector<SimtStepKind> kinds;
  std::vector<std::array<uint8_t, kMaxRecordWords>> word_cycles;
  uint32_t lanes = 0;
  uint32_t l1_banks = 0;
  bool l1_words = false;
  uint32_t node_load_bytes = 4, triangle_load_bytes = 4;  // width of the loads that read a record (l1_words)
  bool wants_words() const { return l1_banks || l1_words; }
  size_t requests() const { return request_end.size(); }
  void add_step(SimtStepKind kind, const uint64_t* step_sectors, uint32_t count) {
    for (uint32_t i = 0; i < count; ++i) sectors.push_back(static_cast<uint32_t>(step_sectors[i]));
    request_end.push_back(static_cast<uint32_t>(sectors.size()));
    kinds.push_back(kind);
    if (wants_words()) word_cycles.push_back({});
  }
};

}  // namespace raycoh
