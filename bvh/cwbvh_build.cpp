// Collapse of a BVH2 into the compressed 8-wide layout of core/cwbvh.h (Ylitie, Karras & Laine, HPG 2017).
//
// Collapse (the paper's section 3.1, our implementation): for every BVH2 inner node n and i in [1, 8], cost(n, i)
// is the least SAH cost of representing n's subtree as at most i subtrees:
//   cost(n, 1) = min(leaf(n), A(n) c_node + split(n, 8))     leaf(n) = A(n) tris(n) c_tri if tris(n) <= 3, else inf
//   cost(n, i) = min(cost(n, i - 1), split(n, i))             split(n, i) = min_k cost(l, k) + cost(r, i - k)
// where A is the surface area relative to the root and a BVH2 leaf costs leaf() for every i. Solved bottom-up
// (children have larger indices in the BVH2's pre-order), then read back top-down from the root, which is
// always an inner node. c_node and c_tri are the BVH2 config's traversal_cost and intersection_cost (1 and 1 by
// default; an assumption of ours, not the paper's constants).
//
// Child slots: for a ray travelling towards octant s (direction signs (-1)^bit), the child whose box centre lies
// furthest back along that direction, relative to the parent's centre, should be visited first, so it goes to
// slot s (core/traverse_cwbvh.h visits slots o, o ^ 1, ... for a ray of octant o). Assignment is greedy: the
// (child, slot) pair of least dot(centre - parent centre, direction of slot) first, until every child has a slot.
// The paper solves the same assignment with an auction. The exact optimum of this cost (commit 3e452d0, reverted)
// did not pay: 0.93-1.01x of greedy's modeled trace speed at 1920x1080 (results/cwbvh/optimal_slots_1920x1080.csv).
//
// Quantisation: p = the node box's low corner; per axis the smallest power-of-two scale with p + 255 scale >= hi;
// child planes rounded outwards (floor for lo, ceil for hi) and then checked on the real value of p + q scale
// (directed rounding), so every decoded child box contains the true one in exact arithmetic.
#include "bvh/cwbvh_build.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/directed_rounding.h"
#include "core/error.h"

namespace raycoh {

void cwbvh_quantize(CwbvhNode& node, const Bounds& box, const Bounds child[kCwbvhWidth], uint32_t slots) {
  node.p = box.lo;
  for (int a = 0; a < 3; ++a) {
    const float lo = box.lo[a], hi = box.hi[a];
    RAYCOH_CHECK(lo <= hi && std::isfinite(lo) && std::isfinite(hi), "cwbvh_quantize: empty or infinite box");
    // Smallest biased exponent e with lo + 255 * 2^(e - 127) >= hi; at least 1 (a normal scale).
    int e = 1;
    const float extent = hi - lo;
    if (extent > 0.f) {
      int exp2 = 0;
      std::frexp(extent / 255.f, &exp2);  // extent / 255 < 2^exp2
      e = std::clamp(exp2 + 127 - 1, 1, 254);
    }
    // The real value of lo + 255 scale (fma_down is at or below it) must reach hi.
    auto reaches = [&](int ex) { return fma_down(255.f, cwbvh_scale(static_cast<uint8_t>(ex)), lo) >= hi; };
    while (e < 254 && !reaches(e)) ++e;
    if (e > 1 && reaches(e - 1)) --e;  // frexp rounding: one lower
    RAYCOH_CHECK(reaches(e), "cwbvh_quantize: extent out of range");
    node.e[a] = static_cast<uint8_t>(e);
  }
  uint8_t* qlo[3] = {node.qlo_x, node.qlo_y, node.qlo_z};
  uint8_t* qhi[3] = {node.qhi_x, node.qhi_y, node.qhi_z};
  for (int s = 0; s < kCwbvhWidth; ++s) {
    for (int a = 0; a < 3; ++a) {
      qlo[a][s] = qhi[a][s] = 0;
      if (!((slots >> s) & 1u)) continue;
      const float p = node.p[a], scale = cwbvh_scale(node.e[a]);
      const float clo = child[s].lo[a], chi = child[s].hi[a];
      RAYCOH_CHECK(clo >= box.lo[a] && chi <= box.hi[a], "cwbvh_quantize: child box outside the node box");
      // Bounds on the real value of p + q scale (the node step's FMAs contain it): at or above for a low plane,
      // at or below for a high one.
      auto decode_up = [&](int q) { return fma_up(static_cast<float>(q), scale, p); };
      auto decode_down = [&](int q) { return fma_down(static_cast<float>(q), scale, p); };
      int l = std::clamp(static_cast<int>(std::floor((clo - p) / scale)), 0, 255);
      while (l > 0 && decode_up(l) > clo) --l;
      int h = std::clamp(static_cast<int>(std::ceil((chi - p) / scale)), 0, 255);
      while (h < 255 && decode_down(h) < chi) ++h;
      RAYCOH_CHECK(decode_up(l) <= clo && decode_down(h) >= chi,
                   "cwbvh_quantize: a decoded box does not contain its child");
      qlo[a][s] = static_cast<uint8_t>(l);
      qhi[a][s] = static_cast<uint8_t>(h);
    }
  }
}

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// A BVH2 subtree that becomes one child slot: a BVH2 leaf, or an inner node kept as an inner node or made a leaf.
struct Entry {
  int32_t ref;
  Bounds box;
  bool leaf;
};

class Collapser {
 public:
  explicit Collapser(const Bvh& bvh2) : in_(bvh2) {}

  Cwbvh run() {
    const size_t n = in_.nodes.size();
    box_.resize(n);
    tris_.assign(n, 0);
    cost_.assign(n, {});
    split_k_.assign(n, {});
    as_leaf_.assign(n, false);
    box_[0] = in_.bounds;
    for (size_t i = 0; i < n; ++i) {
      const BvhNode& b = in_.nodes[i];
      for (int c = 0; c < 2; ++c) {
        if (is_leaf_ref(b.child[c])) {
          if (leaf_count(b.child[c]) > static_cast<uint32_t>(kCwbvhMaxLeafTris))
            throw Error(fmt::format("CWBVH collapse: a BVH2 leaf holds {} triangles; at most {} allowed",
                                    leaf_count(b.child[c]), kCwbvhMaxLeafTris));
        } else {
          box_[b.child[c]] = c == 0 ? Bounds{b.lo0, b.hi0} : Bounds{b.lo1, b.hi1};
        }
      }
    }
    root_area_ = in_.bounds.half_area();
    for (size_t i = n; i-- > 0;) solve(static_cast<int32_t>(i));

    out_.bounds = in_.bounds;
    out_.stats.sah_cost = cost_[0][0];
    out_.nodes.emplace_back();
    emit(0, children_of(0), 0);
    out_.stats.nodes = out_.nodes.size();
    out_.stats.triangles = out_.tris.size();
    out_.stats.children_per_node = static_cast<double>(slots_used_) / static_cast<double>(out_.nodes.size());
    out_.stats.bytes = out_.nodes.size() * sizeof(CwbvhNode) + out_.tris.size() * sizeof(BvhTriangle);
    RAYCOH_CHECK(out_.tris.size() == in_.tris.size(),
                 fmt::format("CWBVH holds {} triangles, the BVH2 {}", out_.tris.size(), in_.tris.size()));
    return std::move(out_);
  }

 private:
  double area(const Bounds& b) const { return root_area_ > 0.f ? double(b.half_area()) / root_area_ : 1.0; }
  uint32_t tri_count(int32_t ref) const { return is_leaf_ref(ref) ? leaf_count(ref) : tris_[ref]; }
  Bounds child_box(int32_t parent, int c) const {
    const BvhNode& b = in_.nodes[parent];
    return c == 0 ? Bounds{b.lo0, b.hi0} : Bounds{b.lo1, b.hi1};
  }
  // cost(ref, i) for i in [1, 8]; a BVH2 leaf costs the same for every i.
  double cost(int32_t ref, const Bounds& box, int i) const {
    if (is_leaf_ref(ref)) return area(box) * leaf_count(ref) * in_.config.intersection_cost;
    return cost_[ref][i - 1];
  }

  void solve(int32_t n) {
    const BvhNode& b = in_.nodes[n];
    const Bounds b0 = child_box(n, 0), b1 = child_box(n, 1);
    tris_[n] = tri_count(b.child[0]) + tri_count(b.child[1]);
    std::array<double, kCwbvhWidth + 1> split{};
    for (int i = 2; i <= kCwbvhWidth; ++i) {
      split[i] = kInf;
      for (int k = 1; k < i; ++k) {
        const double c = cost(b.child[0], b0, k) + cost(b.child[1], b1, i - k);
        if (c < split[i]) {
          split[i] = c;
          split_k_[n][i - 1] = static_cast<uint8_t>(k);
        }
      }
    }
    inner_k_[n] = split_k_[n][kCwbvhWidth - 1];
    const double a = area(box_[n]);
    const double leaf =
        tris_[n] <= static_cast<uint32_t>(kCwbvhMaxLeafTris) ? a * tris_[n] * in_.config.intersection_cost : kInf;
    const double inner = a * in_.config.traversal_cost + split[kCwbvhWidth];
    as_leaf_[n] = leaf <= inner;
    cost_[n][0] = std::min(leaf, inner);
    split_k_[n][0] = 0;
    for (int i = 2; i <= kCwbvhWidth; ++i) {
      if (split[i] < cost_[n][i - 2]) {
        cost_[n][i - 1] = split[i];
      } else {
        cost_[n][i - 1] = cost_[n][i - 2];
        split_k_[n][i - 1] = 0;  // as with i - 1 subtrees
      }
    }
  }

  // The at most i subtrees that represent ref.
  void expand(int32_t ref, const Bounds& box, int i, std::vector<Entry>& out) const {
    if (is_leaf_ref(ref)) {
      if (leaf_count(ref) > 0) out.push_back({ref, box, true});
      return;
    }
    while (i > 1 && split_k_[ref][i - 1] == 0) --i;
    if (i == 1) {
      out.push_back({ref, box, as_leaf_[ref]});
      return;
    }
    const int k = split_k_[ref][i - 1];
    expand(in_.nodes[ref].child[0], child_box(ref, 0), k, out);
    expand(in_.nodes[ref].child[1], child_box(ref, 1), i - k, out);
  }
  // The children of BVH2 inner node n made an 8-wide node: split(n, 8).
  std::vector<Entry> children_of(int32_t n) const {
    std::vector<Entry> out;
    const int k = inner_k_[n];
    expand(in_.nodes[n].child[0], child_box(n, 0), k, out);
    expand(in_.nodes[n].child[1], child_box(n, 1), kCwbvhWidth - k, out);
    return out;
  }
  void gather_tris(int32_t ref, std::vector<uint32_t>& out) const {
    if (is_leaf_ref(ref)) {
      for (uint32_t t = leaf_first(ref); t < leaf_first(ref) + leaf_count(ref); ++t) out.push_back(t);
      return;
    }
    gather_tris(in_.nodes[ref].child[0], out);
    gather_tris(in_.nodes[ref].child[1], out);
  }

  // Fills out_.nodes[index] from its children (BVH2 subtrees) and recurses into its inner children.
  void emit(uint32_t index, const std::vector<Entry>& children, size_t depth) {
    RAYCOH_CHECK(!children.empty() && children.size() <= size_t{kCwbvhWidth},
                 fmt::format("CWBVH node with {} children", children.size()));
    out_.stats.max_depth = std::max(out_.stats.max_depth, depth);
    Bounds box;
    for (const Entry& e : children) box.grow(e.box);
    // Greedy octant slot assignment.
    const Vec3 centre = box.center();
    std::array<int, kCwbvhWidth> slot_child;
    slot_child.fill(-1);
    std::vector<bool> placed(children.size(), false);
    for (size_t round = 0; round < children.size(); ++round) {
      float best = kInf;
      int best_c = -1, best_s = -1;
      for (size_t c = 0; c < children.size(); ++c) {
        if (placed[c]) continue;
        const Vec3 d = children[c].box.center() - centre;
        for (int s = 0; s < kCwbvhWidth; ++s) {
          if (slot_child[s] >= 0) continue;
          const Vec3 dir{(s & 1) ? -1.f : 1.f, (s & 2) ? -1.f : 1.f, (s & 4) ? -1.f : 1.f};
          const float v = dot(d, dir);
          if (best_c < 0 || v < best) {
            best = v;
            best_c = static_cast<int>(c);
            best_s = s;
          }
        }
      }
      placed[best_c] = true;
      slot_child[best_s] = best_c;
    }
    // Inner children consecutive in slot order, then the leaves' triangles in slot order.
    CwbvhNode node{};
    std::array<Bounds, kCwbvhWidth> boxes;
    uint32_t slots = 0, inner_count = 0;
    for (int s = 0; s < kCwbvhWidth; ++s)
      if (slot_child[s] >= 0 && !children[slot_child[s]].leaf) ++inner_count;
    node.child_base = static_cast<uint32_t>(out_.nodes.size());
    node.tri_base = static_cast<uint32_t>(out_.tris.size());
    out_.nodes.resize(out_.nodes.size() + inner_count);
    std::vector<uint32_t> prims;
    for (int s = 0; s < kCwbvhWidth; ++s) {
      if (slot_child[s] < 0) continue;
      const Entry& e = children[slot_child[s]];
      boxes[s] = e.box;
      slots |= 1u << s;
      ++slots_used_;
      if (!e.leaf) {
        node.imask |= static_cast<uint8_t>(1u << s);
        node.meta[s] = cwbvh_inner_meta(s);
        continue;
      }
      prims.clear();
      gather_tris(e.ref, prims);
      RAYCOH_CHECK(prims.size() >= 1 && prims.size() <= size_t{kCwbvhMaxLeafTris}, "CWBVH leaf size");
      const size_t offset = out_.tris.size() - node.tri_base;
      RAYCOH_CHECK(offset + prims.size() <= size_t{kCwbvhMaxNodeTris}, "CWBVH node with more than 24 triangles");
      node.meta[s] = cwbvh_leaf_meta(static_cast<uint32_t>(offset), static_cast<uint32_t>(prims.size()));
      for (uint32_t t : prims) out_.tris.push_back(in_.tris[t]);
      ++out_.stats.leaves;
    }
    cwbvh_quantize(node, box, boxes.data(), slots);
    out_.nodes[index] = node;
    uint32_t next = node.child_base;
    for (int s = 0; s < kCwbvhWidth; ++s) {
      if (slot_child[s] < 0 || children[slot_child[s]].leaf) continue;
      emit(next++, children_of(children[slot_child[s]].ref), depth + 1);
    }
  }

  const Bvh& in_;
  std::vector<Bounds> box_;
  std::vector<uint32_t> tris_;
  std::vector<std::array<double, kCwbvhWidth>> cost_;      // cost_[n][i - 1] = cost(n, i)
  std::vector<std::array<uint8_t, kCwbvhWidth>> split_k_;  // [n][i - 1]: k of split(n, i), 0: as cost(n, i - 1)
  std::vector<uint8_t> inner_k_ = std::vector<uint8_t>(in_.nodes.size());  // k of split(n, 8)
  std::vector<bool> as_leaf_;
  float root_area_ = 0.f;
  size_t slots_used_ = 0;
  Cwbvh out_;
};

}  // namespace

Cwbvh collapse_to_cwbvh(const Bvh& bvh2) {
  RAYCOH_CHECK(!bvh2.nodes.empty(), "CWBVH collapse of an empty BVH2");
  return Collapser(bvh2).run();
}

Cwbvh build_cwbvh(const Scene& scene, const BvhBuildConfig& config) {
  const auto start = std::chrono::steady_clock::now();
  BvhBuildConfig c = config;
  c.max_leaf_size = 1;
  c.min_leaf_size = 1;
  Cwbvh out = collapse_to_cwbvh(build_bvh(scene, c));
  out.stats.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace raycoh
