// Builds the multilevel cuts of a BVH for MLHCC (Xiang et al. 2023, "Faster Ray Tracing through Hierarchy Cut
// Code"); the rule and its reasons are in encoders/mlhcc.cpp.
//
// Parameters
//   lambda  float        (0, 1): a node joins the next cut once its box's surface area is at most lambda times
//                        that of the cut node above it
//   ranks   MlhccRanks   Compressed (rank among siblings under one cut node) | Global (rank in the whole level)
#include "encoders/mlhcc_cuts.h"

#include <fmt/format.h>

#include <algorithm>

#include "core/error.h"

namespace raycoh {
namespace {

// Smallest w with 2^w >= n (0 for n <= 1).
uint32_t bits_for(uint32_t n) {
  uint32_t w = 0;
  while (w < 32 && (uint64_t{1} << w) < n) ++w;
  return w;
}

struct CutParent {
  float area = 0.f;
  uint32_t level = 0;     // 0 for the root
  uint32_t children = 0;  // cut nodes found beneath it so far
};

// One element of the tree on the DFS stack: a child reference with its box's area and the slot that points at it.
struct Visit {
  int32_t ref = 0;
  uint32_t parent_node = 0;
  int slot = -1;  // -1: the root, which is in no cut
  float area = 0.f;
  uint32_t cut_parent = 0;  // index into the CutParent list
};

}  // namespace

MlhccCuts MlhccCutTable::view() const {
  MlhccCuts v;
  v.nodes = nodes;
  v.cuts = cuts.data();
  v.node_count = node_count;
  v.level_count = static_cast<uint32_t>(level_bits.size());
  uint32_t offset = 0;
  for (size_t l = 0; l < level_bits.size(); ++l) {
    v.level_bits[l] = static_cast<uint16_t>(level_bits[l]);
    v.level_offset[l] = static_cast<uint16_t>(offset);
    offset += level_bits[l];
  }
  return v;
}

std::string MlhccCutTable::summary() const {
  std::string bits, sizes;
  for (size_t l = 0; l < level_bits.size(); ++l) {
    bits += fmt::format("{}{}", l ? "/" : "", level_bits[l]);
    sizes += fmt::format("{}{}", l ? "/" : "", level_sizes[l]);
  }
  return fmt::format("levels={} bits={} nodes={}", level_bits.size(), bits.empty() ? "-" : bits,
                     sizes.empty() ? "-" : sizes);
}

MlhccCutTable build_mlhcc_cuts(const Bvh& bvh, float lambda, MlhccRanks ranks) {
  RAYCOH_CHECK(lambda > 0.f && lambda < 1.f, fmt::format("lambda = {}", lambda));
  MlhccCutTable table;
  table.nodes = bvh.nodes.data();
  table.node_count = static_cast<uint32_t>(bvh.nodes.size());
  table.cuts.assign(bvh.nodes.size(), MlhccNodeCut{});
  if (bvh.nodes.empty()) return table;

  const BvhNode& root = bvh.nodes[0];
  Bounds root_box{root.lo0, root.hi0};
  root_box.grow(Bounds{root.lo1, root.hi1});

  std::vector<CutParent> parents = {{root_box.half_area(), 0, 0}};
  std::vector<uint32_t> max_siblings;  // per level, the largest sibling set (Compressed widths)
  std::vector<Visit> stack = {{0, 0, -1, root_box.half_area(), 0}};
  // Pre-order, child 0 first: ranks then follow the node order of the flat BVH, so sorting by the code
  // sorts rays by the tree's own left-to-right order at every level.
  while (!stack.empty()) {
    const Visit v = stack.back();
    stack.pop_back();
    uint32_t cut_parent = v.cut_parent;
    if (v.slot >= 0) {
      const CutParent parent = parents[v.cut_parent];
      if (is_leaf_ref(v.ref) || v.area <= lambda * parent.area) {
        const uint32_t level = parent.level + 1;
        RAYCOH_CHECK(level <= static_cast<uint32_t>(kMlhccMaxLevels), fmt::format("cut level {}", level));
        if (table.level_sizes.size() < level) {
          table.level_sizes.resize(level, 0);
          max_siblings.resize(level, 0);
        }
        const uint32_t sibling = parents[v.cut_parent].children++;
        max_siblings[level - 1] = std::max(max_siblings[level - 1], sibling + 1);
        const uint32_t rank = ranks == MlhccRanks::Compressed ? sibling : table.level_sizes[level - 1];
        ++table.level_sizes[level - 1];
        table.cuts[v.parent_node].level[v.slot] = level;
        table.cuts[v.parent_node].rank[v.slot] = rank;
        if (!is_leaf_ref(v.ref)) {
          parents.push_back({v.area, level, 0});
          cut_parent = static_cast<uint32_t>(parents.size() - 1);
        }
      }
    }
    if (is_leaf_ref(v.ref)) continue;
    const BvhNode& n = bvh.nodes[static_cast<size_t>(v.ref)];
    const auto node = static_cast<uint32_t>(v.ref);
    stack.push_back({n.child[1], node, 1, Bounds{n.lo1, n.hi1}.half_area(), cut_parent});
    stack.push_back({n.child[0], node, 0, Bounds{n.lo0, n.hi0}.half_area(), cut_parent});
  }

  for (size_t l = 0; l < table.level_sizes.size(); ++l)
    table.level_bits.push_back(ranks == MlhccRanks::Compressed ? bits_for(max_siblings[l])
                                                               : bits_for(table.level_sizes[l]));
  return table;
}

}  // namespace raycoh
