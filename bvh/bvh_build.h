// Builds the one flat BVH2 every tracer using our traversal shares, with Embree's rtcBuildBVH (binned SAH,
// branching factor 2, RTC_BUILD_QUALITY_MEDIUM, which is deterministic for any thread count), then flattens it
// into the 64-byte-node layout of core/bvh.h (depth-first, left child first).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/bvh.h"
#include "scenes/scene.h"

namespace raycoh {

struct BvhBuildConfig {
  int max_leaf_size = 4;  // triangles per leaf, [1, kMaxLeafSize]
  int min_leaf_size = 1;
  float traversal_cost = 1.f;     // SAH cost of one node visit
  float intersection_cost = 1.f;  // SAH cost of one triangle test
};

struct BvhStats {
  size_t inner_nodes = 0;
  size_t leaves = 0;
  size_t triangles = 0;        // referenced by leaves (every scene triangle exactly once)
  size_t max_depth = 0;        // root = depth 0; a leaf under the root has depth 1
  double sah_cost = 0.0;       // sum over nodes of (area / root area) x cost, with the config's costs
  size_t bytes = 0;            // nodes + triangles
  double build_seconds = 0.0;  // rtcBuildBVH + flattening
};

struct Bvh {
  std::vector<BvhNode> nodes;
  std::vector<BvhTriangle> tris;
  Bounds bounds;
  BvhStats stats;
  BvhBuildConfig config;
  BvhView view() const {
    return {nodes.data(), tris.data(), static_cast<uint32_t>(nodes.size()), static_cast<uint32_t>(tris.size())};
  }
};

Bvh build_bvh(const Scene& scene, const BvhBuildConfig& config = {});

}  // namespace raycoh
