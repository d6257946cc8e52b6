// Probe kernels for scripts/count-cwbvh-step-instructions: as simt/probe/step_probes.cu for the CWBVH traversal
// (core/traverse_cwbvh.h). Each pair differs only by one step; the state is loaded and stored so that the stack
// stays in local memory as in a real kernel. Compiled for counting only; never linked into raycoh.
#include "core/traverse_cwbvh.h"

using namespace raycoh;

__device__ CwbvhState load_cw_state(const CwbvhState* in) {
  CwbvhState t;
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
  for (int i = 0; i < kTraversalStackSize; ++i) t.stack[i] = s.stack[i];
  return t;
}

__device__ void store_cw_state(const CwbvhState& t, CwbvhState* out) {
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
  CwbvhState t = load_cw_state(in);
  for (int i = 0; i < steps; ++i) t.stack[i & (kTraversalStackSize - 1)] = i;  // keeps the stack in local memory
  store_cw_state(t, out);
}

__global__ void probe_cw_node(CwbvhView bvh, const CwbvhState* in, CwbvhState* out, int steps) {
  CwbvhState t = load_cw_state(in);
  NoCounters c;
  for (int i = 0; i < steps; ++i) cwbvh_node_step(t, bvh, c);
  store_cw_state(t, out);
}

__global__ void probe_cw_triangle(CwbvhView bvh, const CwbvhState* in, CwbvhState* out, int steps) {
  CwbvhState t = load_cw_state(in);
  NoCounters c;
  for (int i = 0; i < steps; ++i) cwbvh_triangle_step(t, bvh, c);
  store_cw_state(t, out);
}

// The triangle test alone, in the same context: the triangle step minus this is its bookkeeping.
__global__ void probe_cw_test(CwbvhView bvh, const CwbvhState* in, CwbvhState* out, int steps) {
  CwbvhState t = load_cw_state(in);
  for (int i = 0; i < steps; ++i) intersect_triangle(t.ray, bvh.tris[i], t.hit);
  store_cw_state(t, out);
}
