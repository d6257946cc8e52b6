// BVH2 construction with Embree's rtcBuildBVH, flattened into the layout of core/bvh.h.
//
// Builder: Embree's binned SAH builder (RTC_BUILD_QUALITY_MEDIUM; Wald, "On fast Construction of SAH-based
// Bounding Volume Hierarchies", RT 2007), branching factor 2. It is deterministic for any thread count, so the
// same scene always gives the same tree. Flattening (Aila & Laine, HPG 2009 layout): nodes depth-first in
// pre-order, child 0 before child 1, each node storing both children's boxes; leaf triangles copied in leaf
// order with the scene's triangle index in BvhTriangle::prim.
//
// Parameters (BvhBuildConfig):
//   max_leaf_size      int    default 4    range [1, kMaxLeafSize = 31]
//   min_leaf_size      int    default 1    range [1, max_leaf_size]; Embree makes a leaf at or below this size
//   traversal_cost     float  default 1    range (0, 1e6]; SAH cost of one node visit
//   intersection_cost  float  default 1    range (0, 1e6]; SAH cost of one triangle test
//
// Guarantees: every scene triangle appears in exactly one leaf; zero-area triangles are kept (their boxes are
// flat or points, which is a valid box); the root is an inner node; the depth of every leaf is below
// kTraversalStackSize, so the traversal stack cannot overflow.
#include "bvh/bvh_build.h"

#include <embree3/rtcore.h>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#if defined(__SANITIZE_THREAD__)
#include <sanitizer/tsan_interface.h>
#endif
#include <new>

#include "core/error.h"
#include "embree/embree_device.h"

namespace raycoh {
namespace {

// Embree's depth counts the root as 1 and our stats count it as 0, so Embree's limit of kTraversalStackSize - 2
// leaves one level of headroom below the stack size; the flattened depth is checked again anyway.
constexpr unsigned kEmbreeMaxDepth = kTraversalStackSize - 2;

// Embree runs the callbacks below on its TBB workers and orders them (a node is made before its children are set;
// every callback returns before rtcBuildBVH does) inside its own code, which ThreadSanitizer does not see (Debian's
// libembree3 is not instrumented). Under TSan (scripts/tsan) each callback therefore acquires and releases the
// build's token (RTCBuildArguments::userPtr), and the builder acquires it after rtcBuildBVH returns: that states
// Embree's ordering, and nothing else, to TSan. Without TSan these are no-ops.
class EmbreeOrdered {
 public:
  explicit EmbreeOrdered(void* token) : token_(token) {
#if defined(__SANITIZE_THREAD__)
    __tsan_acquire(token_);
#endif
  }
  ~EmbreeOrdered() {
#if defined(__SANITIZE_THREAD__)
    __tsan_release(token_);
#endif
  }
  EmbreeOrdered(const EmbreeOrdered&) = delete;
  EmbreeOrdered& operator=(const EmbreeOrdered&) = delete;

 private:
  [[maybe_unused]] void* token_;
};

// The temporary tree Embree builds through the callbacks, in memory owned by the RTCBVH.
struct BuildNode {
  bool is_leaf;
};
struct BuildInner : BuildNode {
  BuildNode* child[2];
  Bounds box[2];
};
struct BuildLeaf : BuildNode {
  uint32_t count;
  // The `count` triangle indices are allocated right behind the struct.
  uint32_t* prims() { return reinterpret_cast<uint32_t*>(this + 1); }
  const uint32_t* prims() const { return reinterpret_cast<const uint32_t*>(this + 1); }
};

void* create_inner(RTCThreadLocalAllocator alloc, unsigned child_count, void* token) {
  const EmbreeOrdered ordered(token);
  RAYCOH_CHECK(child_count == 2, fmt::format("Embree asked for an inner node with {} children", child_count));
  void* mem = rtcThreadLocalAlloc(alloc, sizeof(BuildInner), alignof(BuildInner));
  auto* node = new (mem) BuildInner;
  node->is_leaf = false;
  node->child[0] = node->child[1] = nullptr;
  return node;
}

void set_children(void* node_ptr, void** children, unsigned child_count, void* token) {
  const EmbreeOrdered ordered(token);
  auto* node = static_cast<BuildInner*>(node_ptr);
  for (unsigned i = 0; i < child_count; ++i) node->child[i] = static_cast<BuildNode*>(children[i]);
}

void set_bounds(void* node_ptr, const RTCBounds** bounds, unsigned child_count, void* token) {
  const EmbreeOrdered ordered(token);
  auto* node = static_cast<BuildInner*>(node_ptr);
  for (unsigned i = 0; i < child_count; ++i) {
    node->box[i].lo = {bounds[i]->lower_x, bounds[i]->lower_y, bounds[i]->lower_z};
    node->box[i].hi = {bounds[i]->upper_x, bounds[i]->upper_y, bounds[i]->upper_z};
  }
}

void* create_leaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t count, void* token) {
  const EmbreeOrdered ordered(token);
  RAYCOH_CHECK(count <= static_cast<size_t>(kMaxLeafSize),
               fmt::format("Embree made a leaf of {} triangles; the layout holds at most {}", count, kMaxLeafSize));
  const size_t bytes = sizeof(BuildLeaf) + count * sizeof(uint32_t);
  void* mem = rtcThreadLocalAlloc(alloc, bytes, alignof(BuildLeaf));
  auto* leaf = new (mem) BuildLeaf;
  leaf->is_leaf = true;
  leaf->count = static_cast<uint32_t>(count);
  for (size_t i = 0; i < count; ++i) leaf->prims()[i] = prims[i].primID;
  return leaf;
}

void validate(const BvhBuildConfig& c) {
  if (c.max_leaf_size < 1 || c.max_leaf_size > kMaxLeafSize)
    throw Error(fmt::format("BVH build: max_leaf_size={} is not valid; expected an integer in [1, {}]", c.max_leaf_size,
                            kMaxLeafSize));
  if (c.min_leaf_size < 1 || c.min_leaf_size > c.max_leaf_size)
    throw Error(
        fmt::format("BVH build: min_leaf_size={} is not valid; expected an integer in [1, {}] "
                    "(max_leaf_size)",
                    c.min_leaf_size, c.max_leaf_size));
  if (!(c.traversal_cost > 0.f && c.traversal_cost <= 1e6f))
    throw Error(
        fmt::format("BVH build: traversal_cost={} is not valid; expected a number in (0, 1e6]", c.traversal_cost));
  if (!(c.intersection_cost > 0.f && c.intersection_cost <= 1e6f))
    throw Error(fmt::format("BVH build: intersection_cost={} is not valid; expected a number in (0, 1e6]",
                            c.intersection_cost));
}

// Depth-first, pre-order flattening of Embree's tree into out.nodes / out.tris.
class Flattener {
 public:
  Flattener(const Scene& scene, Bvh& out, float root_area) : scene_(scene), out_(out), root_area_(root_area) {}

  // Appends `node` (whose box is `box`, at `depth`) and returns its child reference.
  int32_t add(const BuildNode* node, const Bounds& box, size_t depth) {
    out_.stats.max_depth = std::max(out_.stats.max_depth, depth);
    if (depth >= static_cast<size_t>(kTraversalStackSize))
      throw Error(
          fmt::format("BVH of scene '{}' is {} levels deep; the traversal stack holds {} (the scene's "
                      "triangle distribution is too uneven)",
                      scene_.name, depth, kTraversalStackSize));
    if (node->is_leaf) return add_leaf(*static_cast<const BuildLeaf*>(node), box);
    const auto& inner = *static_cast<const BuildInner*>(node);
    const size_t index = out_.nodes.size();
    out_.nodes.emplace_back();
    ++out_.stats.inner_nodes;
    out_.stats.sah_cost += area_ratio(box) * out_.config.traversal_cost;
    const int32_t ref0 = add(inner.child[0], inner.box[0], depth + 1);
    const int32_t ref1 = add(inner.child[1], inner.box[1], depth + 1);
    BvhNode& n = out_.nodes[index];  // not earlier: the recursion reallocates the vector
    n.lo0 = inner.box[0].lo;
    n.hi0 = inner.box[0].hi;
    n.lo1 = inner.box[1].lo;
    n.hi1 = inner.box[1].hi;
    n.child[0] = ref0;
    n.child[1] = ref1;
    return static_cast<int32_t>(index);
  }

  int32_t add_leaf(const BuildLeaf& leaf, const Bounds& box) {
    const size_t first = out_.tris.size();
    if (first > kMaxLeafFirst)
      throw Error(fmt::format("scene '{}' has {} triangles; the BVH layout addresses at most {}", scene_.name,
                              scene_.triangle_count(), kMaxLeafFirst));
    for (uint32_t i = 0; i < leaf.count; ++i) {
      const uint32_t prim = leaf.prims()[i];
      BvhTriangle t{};
      t.v0 = scene_.positions[scene_.indices[3 * size_t{prim}]];
      t.v1 = scene_.positions[scene_.indices[3 * size_t{prim} + 1]];
      t.v2 = scene_.positions[scene_.indices[3 * size_t{prim} + 2]];
      t.prim = prim;
      out_.tris.push_back(t);
    }
    ++out_.stats.leaves;
    out_.stats.sah_cost += area_ratio(box) * leaf.count * out_.config.intersection_cost;
    return make_leaf_ref(static_cast<uint32_t>(first), leaf.count);
  }

 private:
  // A root box without area (all triangles on one line or point) makes every ratio 1: a ray that reaches the
  // root then reaches every node.
  double area_ratio(const Bounds& box) const {
    return root_area_ > 0.f ? static_cast<double>(box.half_area()) / root_area_ : 1.0;
  }

  const Scene& scene_;
  Bvh& out_;
  float root_area_;
};

// RAII for the RTCBVH, which owns every BuildNode.
struct EmbreeBvh {
  RTCBVH handle;
  explicit EmbreeBvh(RTCDevice device) : handle(rtcNewBVH(device)) {}
  ~EmbreeBvh() {
    if (handle) rtcReleaseBVH(handle);
  }
  EmbreeBvh(const EmbreeBvh&) = delete;
  EmbreeBvh& operator=(const EmbreeBvh&) = delete;
};

// The scene's triangle boxes as Embree build primitives (ids = triangle indices), grown into bvh.bounds; every
// index and vertex is checked first.
std::vector<RTCBuildPrimitive> triangle_boxes(const Scene& scene, Bvh& bvh) {
  const size_t tri_count = scene.triangle_count();
  std::vector<RTCBuildPrimitive> prims(tri_count);
  for (size_t i = 0; i < tri_count; ++i) {
    Bounds box;
    for (int k = 0; k < 3; ++k) {
      const uint32_t index = scene.indices[3 * i + k];
      if (index >= scene.positions.size())
        throw Error(fmt::format("scene '{}': triangle {} uses vertex {}, but there are {} vertices", scene.name, i,
                                index, scene.positions.size()));
      const Vec3 p = scene.positions[index];
      if (!is_finite(p))
        throw Error(
            fmt::format("scene '{}': triangle {} has a non-finite vertex ({}, {}, {})", scene.name, i, p.x, p.y, p.z));
      box.grow(p);
    }
    bvh.bounds.grow(box);
    prims[i] = {box.lo.x, box.lo.y, box.lo.z, 0u, box.hi.x, box.hi.y, box.hi.z, static_cast<unsigned>(i)};
  }
  return prims;
}

// Runs Embree's builder over `prims` (reordered in place) into the memory of `handle`; returns the root.
const BuildNode* run_embree_builder(const Scene& scene, const BvhBuildConfig& config, RTCBVH handle,
                                    std::vector<RTCBuildPrimitive>& prims) {
  RTCBuildArguments args = rtcDefaultBuildArguments();
  args.buildQuality = RTC_BUILD_QUALITY_MEDIUM;
  args.maxBranchingFactor = 2;
  args.maxDepth = kEmbreeMaxDepth;
  args.sahBlockSize = 1;
  args.minLeafSize = static_cast<unsigned>(config.min_leaf_size);
  args.maxLeafSize = static_cast<unsigned>(config.max_leaf_size);
  args.traversalCost = config.traversal_cost;
  args.intersectionCost = config.intersection_cost;
  args.bvh = handle;
  args.primitives = prims.data();
  args.primitiveCount = prims.size();
  args.primitiveArrayCapacity = prims.size();
  args.createNode = create_inner;
  args.setNodeChildren = set_children;
  args.setNodeBounds = set_bounds;
  args.createLeaf = create_leaf;
  char order_token = 0;  // its address only: see EmbreeOrdered
  args.userPtr = &order_token;
  void* root = rtcBuildBVH(&args);
  { const EmbreeOrdered ordered(&order_token); }
  embree_check(fmt::format("building the BVH of scene '{}'", scene.name));
  RAYCOH_CHECK(root != nullptr, "rtcBuildBVH returned no root without reporting an error");
  return static_cast<const BuildNode*>(root);
}

// Copies Embree's tree into the layout of core/bvh.h.
void flatten_tree(const Scene& scene, const BuildNode* root_node, Bvh& bvh) {
  const size_t tri_count = scene.triangle_count();
  bvh.nodes.reserve(2 * tri_count / static_cast<size_t>(bvh.config.max_leaf_size) + 2);
  bvh.tris.reserve(tri_count);
  const float root_area = bvh.bounds.half_area();
  Flattener flattener(scene, bvh, root_area);
  if (root_node->is_leaf) {
    // The layout's root must be an inner node: wrap the single leaf, with an empty leaf of the same box beside.
    bvh.nodes.emplace_back();
    ++bvh.stats.inner_nodes;
    bvh.stats.sah_cost += 1.0 * bvh.config.traversal_cost;
    const int32_t leaf_ref = flattener.add(root_node, bvh.bounds, 1);
    BvhNode& n = bvh.nodes[0];
    n.lo0 = n.lo1 = bvh.bounds.lo;
    n.hi0 = n.hi1 = bvh.bounds.hi;
    n.child[0] = leaf_ref;
    n.child[1] = make_leaf_ref(0, 0);
    ++bvh.stats.leaves;
  } else {
    flattener.add(root_node, bvh.bounds, 0);
  }
}

}  // namespace

Bvh build_bvh(const Scene& scene, const BvhBuildConfig& config) {
  validate(config);
  const auto start = std::chrono::steady_clock::now();
  const size_t tri_count = scene.triangle_count();
  if (tri_count == 0) throw Error(fmt::format("scene '{}' has no triangles to build a BVH over", scene.name));
  if (scene.indices.size() % 3 != 0)
    throw Error(fmt::format("scene '{}': {} indices is not a multiple of 3", scene.name, scene.indices.size()));
  if (tri_count > kMaxLeafFirst)
    throw Error(fmt::format("scene '{}' has {} triangles; the BVH layout addresses at most {}", scene.name, tri_count,
                            kMaxLeafFirst));

  Bvh bvh;
  bvh.config = config;
  // Embree reorders the primitive array in place; for MEDIUM no spare capacity is needed.
  std::vector<RTCBuildPrimitive> prims = triangle_boxes(scene, bvh);

  RTCDevice device = embree_device();
  EmbreeBvh embree_bvh(device);
  embree_check("creating an Embree BVH");
  const BuildNode* root = run_embree_builder(scene, config, embree_bvh.handle, prims);
  // The tree lives in the RTCBVH's memory: everything is copied out before embree_bvh releases it.
  flatten_tree(scene, root, bvh);

  RAYCOH_CHECK(bvh.tris.size() == tri_count,
               fmt::format("BVH leaves hold {} triangles, the scene has {}", bvh.tris.size(), tri_count));
  bvh.stats.triangles = bvh.tris.size();
  bvh.stats.bytes = bvh.nodes.size() * sizeof(BvhNode) + bvh.tris.size() * sizeof(BvhTriangle);
  bvh.stats.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return bvh;
}

}  // namespace raycoh
