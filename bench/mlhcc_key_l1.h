// MODELED: the L1 of MLHCC's key kernel (key_kernel<mlhcc,u32>, cuda/device_keys.cu) on one pass, replayed on the
// simt cache model (simt/cache_model.h MemoryHierarchy: per-SM sectored LRU L1s in front of one L2). Nothing here
// is measured; raycoh_mlhcc_walks --l1 FILE writes it (results/model/stage-counters/mlhcc-key-l1.md).
//
// The loads are the kernel's SASS (nvcc 13, sm_90; scripts/count-stage-instructions' build, cuobjdump -sass), one
// request per warp instruction whose active lanes are not all off, its sectors the distinct 32-byte sectors its
// active lanes read:
//   - the ray: seven 4-byte loads per lane (org, dir, tmax: bytes 0, 4, 8, 16, 20, 24, 28 of the 32-byte Ray,
//     core/ray.h), every lane of the warp, consecutive rays;
//   - each walk iteration (encoders/keys.h mlhcc_write_path; the origin's walk, then the end point's), for the lanes
//     still in that walk: twelve 4-byte loads of the node's two boxes (bytes 0..47 of the 64-byte BvhNode
//     cuts.nodes[node]), the cut's level word of the child c the point lies in (cuts.cuts[node], 16 bytes: byte
//     8 + 4c), the rank word (byte 4c) in the lanes that write a rank (of nonzero width), the child reference (node
//     byte 48 + 4c) in the lanes that do not stop at the key's last bit. The level tables (level_bits, level_offset)
//     are kernel parameters: constant-cache loads (LDC), not global loads, so not here; nor is the key's store (STG).
// Addresses: each array at its own 256-byte aligned base (cudaMalloc), element i at i x its size.
// Assumptions (each one's direction in the .md): the 8 warps of a block, and the blocks resident on one SM
// together, advance in lockstep, step by step (a step: the ray's loads, or one walk iteration), warp by warp in
// order within a step; block b runs on SM b mod SMs, an SM's blocks in groups of `resident` (one group after
// another); a sector is valid from its first miss (in-flight fills count as hits for later lookups: no MSHR
// timing; `pending` counts the hits on a sector the same warp missed in the same step, the ones a pending-fill
// rule would count as misses); caches start cold (Nsight Compute flushes them before each replayed pass).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "core/bvh.h"
#include "core/ray.h"
#include "encoders/keys.h"
#include "simt/cache_model.h"

namespace raycoh::keyl1 {

// One lane's loads in one walk iteration: the node it reads, the child c its point lies in, whether it loads the
// rank word and the child reference.
struct WalkStep {
  int32_t node = 0;
  uint8_t child = 0;
  bool rank = false;
  bool next = false;
};

// One lane of a warp: its ray (index into the batch) and its two walks (origin, end point).
struct Lane {
  bool active = false;
  uint64_t ray = 0;
  std::array<std::vector<WalkStep>, 2> walk;
};
using Warp = std::array<Lane, 32>;

// The arrays' base addresses (each 256-byte aligned).
struct Layout {
  uint64_t rays = 0, nodes = 0, cuts = 0;
};
// Bases one after another, each rounded up to 256 bytes: rays (n), nodes, cuts.
inline Layout packed_layout(uint64_t rays, uint64_t nodes) {
  auto up = [](uint64_t a) { return (a + 255) / 256 * 256; };
  Layout l;
  l.rays = 256;
  l.nodes = up(l.rays + rays * sizeof(Ray));
  l.cuts = up(l.nodes + nodes * sizeof(BvhNode));
  return l;
}

enum Source { kRay, kNode, kCut, kSources };
struct Counts {
  uint64_t warps = 0;
  std::array<uint64_t, kSources> requests{}, sectors{}, misses{}, pending{};
  std::array<uint64_t, kSources> miss_steps{};  // warp steps in which this source's loads missed at least once
  uint64_t l2_misses = 0;                       // L1 misses that also miss the L2 (DRAM sectors)
  uint64_t total(const std::array<uint64_t, kSources>& a) const { return a[kRay] + a[kNode] + a[kCut]; }
};

// The byte offsets of the twelve box loads, in the SASS's issue order: the origin's loop, the end point's.
constexpr std::array<std::array<uint32_t, 12>, 2> kBoxLoads = {
    {{0, 12, 4, 16, 8, 20, 24, 36, 28, 40, 32, 44}, {0, 12, 24, 36, 4, 16, 28, 40, 8, 20, 32, 44}}};
constexpr std::array<uint32_t, 7> kRayLoads = {0, 4, 8, 16, 20, 24, 28};

class Replay {
 public:
  Replay(const CacheModelConfig& config, Layout layout)
      : memory_(config), layout_(layout), sector_(config.sector_bytes) {}

  // One SM's group of resident warps, in lockstep: step 0 the ray's loads, then every warp's origin walk, then its
  // end walk, one iteration a step; a warp whose walks are done issues nothing.
  void replay_group(uint32_t sm, const Warp* warps, size_t count) {
    size_t steps = 0;
    for (size_t i = 0; i < count; ++i) steps = std::max(steps, warp_steps(warps[i]));
    for (size_t s = 0; s < steps; ++s)
      for (size_t i = 0; i < count; ++i) issue_step(sm, warps[i], s);
    counts_.warps += count;
  }
  const Counts& counts() const { return counts_; }

  // A warp's steps: 1 (the ray) + its origin walk's iterations + its end walk's (each the largest of its lanes).
  static size_t warp_steps(const Warp& w) {
    size_t o = 0, e = 0;
    for (const Lane& l : w) {
      o = std::max(o, l.walk[0].size());
      e = std::max(e, l.walk[1].size());
    }
    return 1 + o + e;
  }

  // One request: the distinct sectors of `addresses` (the active lanes' bytes).
  void request(uint32_t sm, Source source, std::vector<uint64_t>& addresses) {
    if (addresses.empty()) return;
    for (uint64_t& a : addresses) a /= sector_;
    std::sort(addresses.begin(), addresses.end());
    addresses.erase(std::unique(addresses.begin(), addresses.end()), addresses.end());
    ++counts_.requests[source];
    counts_.sectors[source] += addresses.size();
    for (uint64_t sector : addresses) {
      const MemoryLevel level = memory_.access(sm, sector);
      if (level == MemoryLevel::L1) {
        if (std::find(missed_.begin(), missed_.end(), sector) != missed_.end()) ++counts_.pending[source];
        continue;
      }
      ++counts_.misses[source];
      if (level == MemoryLevel::Dram) ++counts_.l2_misses;
      missed_.push_back(sector);
    }
  }

 private:
  void issue_step(uint32_t sm, const Warp& w, size_t step) {
    const std::array<uint64_t, kSources> before = counts_.misses;
    issue_loads(sm, w, step);
    for (int s = 0; s < kSources; ++s)
      if (counts_.misses[s] > before[s]) ++counts_.miss_steps[s];
  }
  void issue_loads(uint32_t sm, const Warp& w, size_t step) {
    missed_.clear();
    if (step == 0) {
      for (uint32_t offset : kRayLoads) {
        lanes_.clear();
        for (const Lane& l : w)
          if (l.active) lanes_.push_back(layout_.rays + l.ray * sizeof(Ray) + offset);
        request(sm, kRay, lanes_);
      }
      return;
    }
    size_t origin = 0;
    for (const Lane& l : w) origin = std::max(origin, l.walk[0].size());
    const int walk = step - 1 < origin ? 0 : 1;
    const size_t t = walk == 0 ? step - 1 : step - 1 - origin;
    issue_iteration(sm, w, walk, t);
  }

  // Iteration t of one walk: the box loads, the level word, the rank word, the child reference.
  void issue_iteration(uint32_t sm, const Warp& w, int walk, size_t t) {
    auto each = [&](Source source, auto address) {
      lanes_.clear();
      for (const Lane& l : w)
        if (l.active && t < l.walk[walk].size()) {
          const WalkStep& s = l.walk[walk][t];
          const uint64_t a = address(s);  // 0: this lane does not load (every real address is past 256)
          if (a != 0) lanes_.push_back(a);
        }
      request(sm, source, lanes_);
    };
    auto node = [&](const WalkStep& s) { return layout_.nodes + uint64_t(s.node) * sizeof(BvhNode); };
    auto cut = [&](const WalkStep& s) { return layout_.cuts + uint64_t(s.node) * sizeof(MlhccNodeCut); };
    for (uint32_t offset : kBoxLoads[walk]) each(kNode, [&](const WalkStep& s) { return node(s) + offset; });
    each(kCut, [&](const WalkStep& s) { return cut(s) + 8 + 4u * s.child; });
    each(kCut, [&](const WalkStep& s) { return s.rank ? cut(s) + 4u * s.child : 0; });
    each(kNode, [&](const WalkStep& s) { return s.next ? node(s) + 48 + 4u * s.child : 0; });
  }

  MemoryHierarchy memory_;
  Layout layout_;
  uint64_t sector_;
  Counts counts_;
  std::vector<uint64_t> lanes_, missed_;
};

// The loads of one walk: the nodes mlhcc_write_path reads (its on_iteration(node)), each iteration's child c
// (locate_child, as the loop), and whether the iteration loads the rank and the child reference: the loop returns
// before both when the level's bit offset is at or past `needed_bits` (encoders/keys.h), and reads the rank only
// when the child is in a cut (level > 0) of a nonzero width at an offset under 64 (CodeWriter::put's condition,
// into which nvcc sinks the load: the SASS skips it when the width is 0 or the offset past 63).
inline void record_walk(const MlhccCuts& cuts, Vec3 p, int field_stride, int field_index, int needed_bits,
                        std::vector<WalkStep>& out) {
  out.clear();
  uint64_t code = 0;
  mlhcc_write_path(cuts, p, field_stride, field_index, needed_bits, code, [&](int32_t node) {
    WalkStep s;
    s.node = node;
    s.child = static_cast<uint8_t>(locate_child(cuts.nodes[node], p));
    const uint32_t level = cuts.cuts[node].level[s.child];
    const int width = level > 0 ? cuts.level_bits[level - 1] : 0;
    const int offset = level > 0 ? field_stride * cuts.level_offset[level - 1] + field_index * width : 0;
    const bool stops = level > 0 && offset >= needed_bits;
    s.rank = level > 0 && !stops && width > 0 && offset < 64;
    s.next = !stops;
    out.push_back(s);
  });
}

// Whether a recorded walk is one the loop can make: every iteration but the last loads the child reference, and a
// last one that loads it found a leaf there (or ran kMlhccMaxLevels iterations). A check of record_walk's rule.
inline bool walk_is_consistent(const MlhccCuts& cuts, const std::vector<WalkStep>& walk) {
  for (size_t i = 0; i + 1 < walk.size(); ++i)
    if (!walk[i].next) return false;
  if (walk.empty() || !walk.back().next || walk.size() == size_t(kMlhccMaxLevels)) return true;
  return is_leaf_ref(cuts.nodes[walk.back().node].child[walk.back().child]);
}

}  // namespace raycoh::keyl1
