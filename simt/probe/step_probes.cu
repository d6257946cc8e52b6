// Probe kernels for scripts/count-step-instructions: each pair differs only by one traversal step, so the
// difference of their instruction counts is what that step issues per warp (every branch of the step counted
// once). The steps run inside a loop of unknown trip count, as in the real kernel, so that the compiler keeps
// the traversal stack in local memory as it does there (a probe without the loop lets ptxas promote the stack
// to registers and index it through select chains). Compiled for counting only; never linked into raycoh.
#include "core/traverse.h"

using namespace raycoh;

__device__ TraversalState load_state(const TraversalState* in) {
  TraversalState t;
  const TraversalState& s = in[threadIdx.x];
  t.ray = s.ray;
  t.hit = s.hit;
  t.node_ref = s.node_ref;
  t.leaf_ref = s.leaf_ref;
  t.sp = s.sp;
  for (int i = 0; i < kTraversalStackSize; ++i) t.stack[i] = s.stack[i];
  return t;
}

__device__ void store_state(const TraversalState& t, TraversalState* out) {
  out[threadIdx.x].hit = t.hit;
  out[threadIdx.x].node_ref = t.node_ref;
  out[threadIdx.x].leaf_ref = t.leaf_ref;
  out[threadIdx.x].sp = t.sp;
  out[threadIdx.x].stack[0] = t.stack[t.sp & (kTraversalStackSize - 1)];  // keeps the stack live in every probe
}

__global__ void probe_base(BvhView, const TraversalState* in, TraversalState* out, int steps) {
  TraversalState t = load_state(in);
  for (int i = 0; i < steps; ++i) t.stack[i & (kTraversalStackSize - 1)] = i;  // keeps the stack in local memory
  store_state(t, out);
}

__global__ void probe_node(BvhView bvh, const TraversalState* in, TraversalState* out, int steps) {
  TraversalState t = load_state(in);
  NoCounters c;
  for (int i = 0; i < steps; ++i) node_step(t, bvh, c);
  store_state(t, out);
}

__global__ void probe_leaf(BvhView bvh, const TraversalState* in, TraversalState* out, int steps) {
  TraversalState t = load_state(in);
  NoCounters c;
  for (int i = 0; i < steps; ++i) leaf_step(t, bvh, c);
  store_state(t, out);
}

// One triangle test per iteration, in the traversal's own context (state loaded as the leaf loop has it).
__global__ void probe_triangle(BvhView bvh, const TraversalState* in, TraversalState* out, int steps) {
  TraversalState t = load_state(in);
  for (int i = 0; i < steps; ++i) intersect_triangle(t.ray, bvh.tris[i], t.hit);
  store_state(t, out);
}

// A warp's start of a ray: prepare the ray and the traversal state (traversal_begin), against a copy of the ray.
__global__ void probe_begin_base(const Ray* rays, TraversalState* out) {
  const Ray r = rays[threadIdx.x];
  out[threadIdx.x].hit.t = r.org.x + r.org.y + r.org.z + r.dir.x + r.dir.y + r.dir.z + r.tmin + r.tmax;
}

__global__ void probe_begin(const Ray* rays, TraversalState* out) {
  TraversalState t;
  traversal_begin(t, rays[threadIdx.x]);
  store_state(t, out);
}

// The tuned kernel's steps (WideFetch, core/traverse.h): the same steps on a state whose stack is apart (a local
// array of the probe's, as closest_hit keeps it), nodes and triangles read with 16-byte loads.
using WideState = TraversalStateOf<StackRefOf<int32_t>>;

__device__ WideState load_wide_state(const TraversalState* in, int32_t* entries) {
  WideState t;
  const TraversalState& s = in[threadIdx.x];
  t.ray = s.ray;
  t.hit = s.hit;
  t.node_ref = s.node_ref;
  t.leaf_ref = s.leaf_ref;
  t.sp = s.sp;
  for (int i = 0; i < kTraversalStackSize; ++i) entries[i] = s.stack[i];
  t.stack.entry = entries;
  return t;
}

// Stores every field, the ray too: with the state in registers, a base probe that left the ray unused would not
// load it, and its loads would be counted as the step's.
__device__ void store_wide_state(const WideState& t, TraversalState* out) {
  out[threadIdx.x].ray = t.ray;
  out[threadIdx.x].hit = t.hit;
  out[threadIdx.x].node_ref = t.node_ref;
  out[threadIdx.x].leaf_ref = t.leaf_ref;
  out[threadIdx.x].sp = t.sp;
  out[threadIdx.x].stack[0] = t.stack[t.sp & (kTraversalStackSize - 1)];
}

__global__ void probe_wide_base(BvhView, const TraversalState* in, TraversalState* out, int steps) {
  int32_t entries[kTraversalStackSize];
  WideState t = load_wide_state(in, entries);
  // The loop without local accesses (the stack apart stays in local memory through its dynamic index): the
  // difference to the step probes then counts the step's own pushes and pops. No probe loop is unrolled: with the
  // state in registers nvcc would unroll this one and the difference would lose its instructions.
#pragma unroll 1
  for (int i = 0; i < steps; ++i) t.node_ref ^= i;
  store_wide_state(t, out);
}

__global__ void probe_wide_node(BvhView bvh, const TraversalState* in, TraversalState* out, int steps) {
  int32_t entries[kTraversalStackSize];
  WideState t = load_wide_state(in, entries);
  NoCounters c;
#pragma unroll 1
  for (int i = 0; i < steps; ++i) node_step<NoCounters, WideFetch>(t, bvh, c);
  store_wide_state(t, out);
}

__global__ void probe_wide_leaf(BvhView bvh, const TraversalState* in, TraversalState* out, int steps) {
  int32_t entries[kTraversalStackSize];
  WideState t = load_wide_state(in, entries);
  NoCounters c;
#pragma unroll 1
  for (int i = 0; i < steps; ++i) leaf_step<NoCounters, NoAlphaTest, WideFetch>(t, bvh, c);
  store_wide_state(t, out);
}

__global__ void probe_wide_triangle(BvhView bvh, const TraversalState* in, TraversalState* out, int steps) {
  int32_t entries[kTraversalStackSize];
  WideState t = load_wide_state(in, entries);
#pragma unroll 1
  for (int i = 0; i < steps; ++i) intersect_triangle(t.ray, load_triangle_wide(bvh.tris, i), t.hit);
  store_wide_state(t, out);
}

// The tuned kernel's start of a ray: traversal_begin on a state whose stack is apart.
__global__ void probe_wide_begin(const Ray* rays, TraversalState* out) {
  int32_t entries[kTraversalStackSize];
  WideState t;
  t.stack.entry = entries;
  traversal_begin(t, rays[threadIdx.x]);
  store_wide_state(t, out);
}
