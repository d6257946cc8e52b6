// Probe kernels for scripts/count-cwbvh-step-instructions: as simt/probe/step_probes.cu for the CWBVH traversal
// (core/traverse_cwbvh.h). Each pair differs only by one step; the state is loaded and stored so that the stack
// stays in local memory as in a real kernel, apart from the state (StackRefOf, as closest_hit_cwbvh keeps it). Compiled
// for counting only; never linked into raycoh.
#include "core/traverse_cwbvh.h"

using namespace raycoh;

using ApartState = CwbvhStateOf<StackRefOf<uint64_t>>;

__device__ ApartState load_cw_state(const CwbvhState* in, uint64_t* entries) {
  ApartState t;
  const CwbvhState& s = in[threadIdx.x];
  t.ray = s.ray;
  t.hit = s.hit;
  t.octant = s.octant;
  t.node_base = s.node_base;
  t.node_hits = s.node_hits;
  t.node_imask = s.node_imask;
  t.tri_base = s.tri_base;
  t.tri_hits = s.tri_hits;
  t.sp = s.sp;
  for (int i = 0; i < kTraversalStackSize; ++i) entries[i] = s.stack[i];
  t.stack.entry = entries;
  return t;
}

// Stores every field, the ray too: with the state in registers, a base probe that left the ray unused would not
// load it, and its loads would be counted as the step's.
__device__ void store_cw_state(const ApartState& t, CwbvhState* out) {
  out[threadIdx.x].ray = t.ray;
  out[threadIdx.x].octant = t.octant;
  out[threadIdx.x].hit = t.hit;
  out[threadIdx.x].node_base = t.node_base;
  out[threadIdx.x].node_hits = t.node_hits;
  out[threadIdx.x].node_imask = t.node_imask;
  out[threadIdx.x].tri_base = t.tri_base;
  out[threadIdx.x].tri_hits = t.tri_hits;
  out[threadIdx.x].sp = t.sp;
  out[threadIdx.x].stack[0] = t.stack[t.sp & (kTraversalStackSize - 1)];  // keeps the stack live in every probe
}

__global__ void probe_cw_base(CwbvhView, const CwbvhState* in, CwbvhState* out, int steps) {
  uint64_t entries[kTraversalStackSize];
  ApartState t = load_cw_state(in, entries);
  // The loop without local accesses (the stack apart stays in local memory through its dynamic index): the
  // difference to the step probes then counts the steps' own pushes and pops.
#pragma unroll 1
  for (int i = 0; i < steps; ++i) t.node_base ^= static_cast<uint32_t>(i);
  store_cw_state(t, out);
}

__global__ void probe_cw_node(CwbvhView bvh, const CwbvhState* in, CwbvhState* out, int steps) {
  uint64_t entries[kTraversalStackSize];
  ApartState t = load_cw_state(in, entries);
  NoCounters c;
#pragma unroll 1
  for (int i = 0; i < steps; ++i) cwbvh_node_step(t, bvh, c);
  store_cw_state(t, out);
}

__global__ void probe_cw_triangle(CwbvhView bvh, const CwbvhState* in, CwbvhState* out, int steps) {
  uint64_t entries[kTraversalStackSize];
  ApartState t = load_cw_state(in, entries);
  NoCounters c;
#pragma unroll 1
  for (int i = 0; i < steps; ++i) cwbvh_triangle_step(t, bvh, c);
  store_cw_state(t, out);
}

// The triangle test alone, in the same context: the triangle step minus this is its bookkeeping.
__global__ void probe_cw_test(CwbvhView bvh, const CwbvhState* in, CwbvhState* out, int steps) {
  uint64_t entries[kTraversalStackSize];
  ApartState t = load_cw_state(in, entries);
#pragma unroll 1
  for (int i = 0; i < steps; ++i) intersect_triangle(t.ray, load_triangle_wide(bvh.tris, i), t.hit);
  store_cw_state(t, out);
}
