// What the warp model (simt/simt.h) hands to the timing model (simt/timed_replay.h): one warp's steps in issue
// order, each with its kind and the sectors it requests. Host only.
#pragma once

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

// Step r requests sectors[begin(r), request_end[r]), begin(0) = 0 and begin(r) = request_end[r - 1]; kinds[r] is
// its kind (leaf steps request nothing: the leaf reference came with its parent node). Sector numbers are byte
// address / sector_bytes. `lanes` is the number of rays the warp holds (the last warp of a batch may hold fewer).
// With `l1_banks` > 0 (set before tracing), word_cycles[r][w] holds l1_bank_cycles of the sectors that the lanes'
// 16-byte word w of the step's record lies in (0 beyond the record and for leaf steps).
struct WarpTrace {
  std::vector<uint32_t> sectors;
  std::vector<uint32_t> request_end;
  std::vector<SimtStepKind> kinds;
  std::vector<std::array<uint8_t, kMaxRecordWords>> word_cycles;
  uint32_t lanes = 0;
  uint32_t l1_banks = 0;
  size_t requests() const { return request_end.size(); }
  void add_step(SimtStepKind kind, const uint64_t* step_sectors, uint32_t count) {
    for (uint32_t i = 0; i < count; ++i) sectors.push_back(static_cast<uint32_t>(step_sectors[i]));
    request_end.push_back(static_cast<uint32_t>(sectors.size()));
    kinds.push_back(kind);
    if (l1_banks) word_cycles.push_back({});
  }
};

}  // namespace raycoh
