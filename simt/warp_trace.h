// What the warp model (simt/simt.h) hands to the timing model (simt/timed_replay.h): one warp's steps in issue
// order, each with its kind and the sectors it requests. Host only.
#pragma once

#include <cstdint>
#include <vector>

namespace raycoh {

enum class SimtStepKind : uint8_t { Node, Leaf, Triangle };

// Step r requests sectors[begin(r), request_end[r]), begin(0) = 0 and begin(r) = request_end[r - 1]; kinds[r] is
// its kind (leaf steps request nothing: the leaf reference came with its parent node). Sector numbers are byte
// address / sector_bytes. `lanes` is the number of rays the warp holds (the last warp of a batch may hold fewer).
struct WarpTrace {
  std::vector<uint32_t> sectors;
  std::vector<uint32_t> request_end;
  std::vector<SimtStepKind> kinds;
  uint32_t lanes = 0;
  size_t requests() const { return request_end.size(); }
  void add_step(SimtStepKind kind, const uint64_t* step_sectors, uint32_t count) {
    for (uint32_t i = 0; i < count; ++i) sectors.push_back(static_cast<uint32_t>(step_sectors[i]));
    request_end.push_back(static_cast<uint32_t>(sectors.size()));
    kinds.push_back(kind);
  }
};

}  // namespace raycoh
