// Builds the compressed 8-wide BVH of core/cwbvh.h by collapsing a BVH2 (Ylitie, Karras & Laine, HPG 2017):
// the SAH-optimal choice of which BVH2 nodes become 8-wide nodes and which subtrees become leaves of at most 3
// triangles (a dynamic program over the BVH2, section 3.1 of the paper), octant-ordered child slots, child boxes
// quantised outwards to 8 bits per plane.
#pragma once

#include <cstddef>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/cwbvh.h"

namespace raycoh {

struct CwbvhStats {
  size_t nodes = 0;
  size_t leaves = 0;     // leaf slots (1 to 3 triangles each)
  size_t triangles = 0;  // every scene triangle exactly once
  size_t max_depth = 0;  // root = 0
  double children_per_node = 0;
  double sah_cost = 0.0;       // the collapse's SAH cost of the root (BvhBuildConfig costs, areas / root area)
  size_t bytes = 0;            // nodes + triangles
  double build_seconds = 0.0;  // the leaf-size-1 BVH2 and the collapse
};

struct Cwbvh {
  std::vector<CwbvhNode> nodes;
  std::vector<BvhTriangle> tris;
  Bounds bounds;
  CwbvhStats stats;
  CwbvhView view() const {
    return {nodes.data(), tris.data(), static_cast<uint32_t>(nodes.size()), static_cast<uint32_t>(tris.size())};
  }
};

// Collapses `bvh2`, whose leaves must hold at most kCwbvhMaxLeafTris triangles (raycoh::Error otherwise). SAH
// costs are bvh2.config's traversal_cost (per node) and intersection_cost (per triangle).
Cwbvh collapse_to_cwbvh(const Bvh& bvh2);

// What the tracers use: Embree's BVH2 with the given config at leaf size 1 (the paper collapses a BVH2 of
// single-triangle leaves, so that the collapse alone decides which triangles share a leaf), collapsed.
Cwbvh build_cwbvh(const Scene& scene, const BvhBuildConfig& config = {});

// Sets node.p, node.e and the quantised boxes of the slots whose bit is set in `slots`: each decoded box
// (cwbvh_child_box) contains child[slot]; every child box must lie inside `box`. Exposed for tests.
void cwbvh_quantize(CwbvhNode& node, const Bounds& box, const Bounds child[kCwbvhWidth], uint32_t slots);

}  // namespace raycoh
