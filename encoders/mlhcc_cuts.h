// The multilevel BVH cuts behind the MLHCC encoder (encoders/mlhcc.cpp explains the rule), built once per BVH on
// the host; MlhccCutTable::view() is the plain MlhccCuts (encoders/keys.h) that host and device code read.
#pragma once

#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "encoders/keys.h"

namespace raycoh {

// How a cut node's rank is numbered.
enum class MlhccRanks {
  Compressed,  // within its parent cut node: level width = bits of the largest sibling set (the default)
  Global,      // within its whole level: level width = bits of the level's size (uncompressed, for comparison)
};

struct MlhccCutTable {
  std::vector<MlhccNodeCut> cuts;  // one per BVH node
  const BvhNode* nodes = nullptr;  // the BVH the table was built for (it must outlive the table's views)
  uint32_t node_count = 0;
  std::vector<uint32_t> level_bits;   // per cut level (level 1 first)
  std::vector<uint32_t> level_sizes;  // cut nodes per level
  MlhccCuts view() const;
  // "levels=3 bits=6/5/4 nodes=40/210/900", for reports.
  std::string summary() const;
};

// Cuts of bvh for area ratio lambda in (0, 1).
MlhccCutTable build_mlhcc_cuts(const Bvh& bvh, float lambda, MlhccRanks ranks);

}  // namespace raycoh
