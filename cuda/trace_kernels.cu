// The GPU traversal kernels behind cuda/trace_kernels.h: persistent-thread and one-thread-per-ray closest-hit
// kernels, and the warp-synchronous counting kernel that reproduces simt/simt.h.
//
// Persistent threads follow Aila & Laine ("Understanding the Efficiency of Ray Traversal on GPUs", HPG 2009,
// section 3): launch only as many warps as the GPU holds at once; lane 0 of a warp takes 32 ray indices with one
// atomicAdd on a global counter and broadcasts the base with __shfl_sync, every lane traces its ray with the
// while-while loop of core/traverse.h, and the warp fetches again. Fetching whole warps of consecutive rays keeps
// the batch order's warp composition (DESIGN.md section 1), which is what the generators and encoders shape.
//
// Counting (simt/simt.h, "Reproducing it in CUDA"): every loop is warp-uniform with explicit masks from
// __ballot_sync over all 32 lanes (lanes past the end of the batch stay in the loops with false predicates), the
// node-loop break is `(ballot(has_leaf) & N) == N`, steps are counted from node_ref / leaf_ref before
// node_step / leaf_step run, and the triangle sub-steps of a leaf step are j = 0 .. __reduce_max_sync(count) - 1.
// Distinct lines and sectors of a step are counted exactly as the size of the union of the lanes' unit ranges:
// a unit of lane i counts unless a lower active lane's range covers it (32 __shfl_sync rounds per step). This is
// one rule for nodes and triangles, for any line and sector size, including triangles straddling two lines.
//
// Alpha MASK cut-outs: every kernel is a template on the traversal's filter policy (core/alpha_mask.h) and gets
// the filter by value. AlphaTest holds the device copies of the scene's mask arrays and runs alpha_opaque() of
// the shared header at each candidate hit, exactly as the CPU tracers do; NoAlphaTest (scenes without masks) is
// empty and compiles to the kernels that ran before masks existed.
// (No fmt here: its consteval format strings do not compile under nvcc 13.)
#include <cuda_runtime.h>

#include <algorithm>
#include <string>

#include "core/error.h"
#include "core/traverse.h"
#include "core/traverse_cwbvh.h"
#include "cuda/cuda_check.cuh"
#include "cuda/trace_kernels.h"

namespace raycoh::cuda {

namespace {

constexpr unsigned kFullMask = 0xffffffffu;
constexpr int kWarp = 32;

// Rays are 32 bytes and buffers come from cudaMalloc (256-byte aligned): two 16-byte read-only loads.
__device__ __forceinline__ Ray load_ray(const Ray* rays, size_t i) {
  const float4* p = reinterpret_cast<const float4*>(rays + i);
  const float4 a = __ldg(p), b = __ldg(p + 1);
  Ray r;
  r.org = Vec3{a.x, a.y, a.z};
  r.tmin = a.w;
  r.dir = Vec3{b.x, b.y, b.z};
  r.tmax = b.w;
  return r;
}

// Hits are 16 bytes: one store.
__device__ __forceinline__ void store_hit(Hit* hits, size_t i, const Hit& h) {
  reinterpret_cast<float4*>(hits)[i] = make_float4(h.t, __uint_as_float(h.prim), h.u, h.v);
}

// The closest hit of one ray in either layout under the filter: the shared traversals, unchanged (with
// NoAlphaTest these are closest_hit(bvh, r) and closest_hit_cwbvh(bvh, r), the same instantiations).
template <class Filter>
__device__ __forceinline__ Hit trace_ray(const BvhView& bvh, const Ray& r, const Filter& filter) {
  NoCounters none;
  return closest_hit(bvh, r, none, filter);
}
// The tuned BVH2 kernel's view: the same arrays, read with 16-byte loads and the stack apart (WideFetch).
struct WideBvhView {
  BvhView bvh;
};
template <class Filter>
__device__ __forceinline__ Hit trace_ray(const WideBvhView& v, const Ray& r, const Filter& filter) {
  NoCounters none;
  return closest_hit<NoCounters, Filter, WideFetch>(v.bvh, r, none, filter);
}
template <class Filter>
__device__ __forceinline__ Hit trace_ray(const CwbvhView& bvh, const Ray& r, const Filter& filter) {
  NoCounters none;
  return closest_hit_cwbvh(bvh, r, none, filter);
}

template <bool Indirect, class View, class Filter>
__global__ void simple_kernel(View bvh, Filter filter, const Ray* rays, const uint32_t* order, size_t count,
                              Hit* hits) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (i >= count) return;
  store_hit(hits, i, trace_ray(bvh, load_ray(rays, Indirect ? order[i] : i), filter));
}

// blockDim.x is a multiple of 32, so every warp is full and reaches the __shfl_sync with all 32 lanes.
template <bool Indirect, class View, class Filter>
__global__ void persistent_kernel(View bvh, Filter filter, const Ray* rays, const uint32_t* order, size_t count,
                                  Hit* hits, unsigned long long* next_ray) {
  const unsigned lane = threadIdx.x & (kWarp - 1);
  for (;;) {
    unsigned long long base = 0;
    if (lane == 0) base = atomicAdd(next_ray, static_cast<unsigned long long>(kWarp));
    base = __shfl_sync(kFullMask, base, 0);
    if (base >= count) return;
    const size_t i = static_cast<size_t>(base) + lane;
    if (i < count) store_hit(hits, i, trace_ray(bvh, load_ray(rays, Indirect ? order[i] : i), filter));
  }
}

// ---- counting ---------------------------------------------------------------------------------------------

// Size of the union of the unit ranges [first, last] of the active lanes (last - first < 32); all 32 lanes call it.
// Each unit of a lane counts once, unless a lower active lane covers it: the union is counted exactly once.
__device__ __forceinline__ uint32_t distinct_units(bool active, uint32_t first, uint32_t last) {
  const unsigned lane = threadIdx.x & (kWarp - 1);
  const uint32_t span = active ? last - first + 1u : 0u;
  uint32_t covered = 0;  // bit k: unit first + k is covered by a lower active lane
  for (int j = 0; j < kWarp; ++j) {
    const uint32_t first_j = __shfl_sync(kFullMask, first, j);
    const uint32_t span_j = __shfl_sync(kFullMask, span, j);
    if (static_cast<unsigned>(j) < lane && span_j > 0) {
      const uint32_t last_j = first_j + (span_j - 1u);
      for (uint32_t k = 0; k < span; ++k) {
        const uint32_t u = first + k;
        if (first_j <= u && u <= last_j) covered |= 1u << k;
      }
    }
  }
  const uint32_t own = span - static_cast<uint32_t>(__popc(covered));
  return __reduce_add_sync(kFullMask, own);
}

// Distinct lines (or sectors) of `unit` bytes among the active lanes' byte ranges [addr, addr + bytes). One call
// site for all lanes: the shuffles inside must be reached by the whole warp at the same instruction.
__device__ __forceinline__ uint32_t units_of(bool active, uint64_t addr, uint32_t bytes, uint32_t unit) {
  const auto first = static_cast<uint32_t>(addr / unit);
  const auto last = static_cast<uint32_t>((addr + bytes - 1) / unit);
  return distinct_units(active, first, last);
}

template <bool Indirect, class Filter>
__global__ void counting_kernel(BvhView bvh, Filter filter, const Ray* rays, const uint32_t* order, size_t count,
                                Hit* hits, SimtConfig layout, WarpStepCounters* out, size_t warps) {
  // A whole warp leaves together here: blockDim.x is a multiple of 32.
  const size_t warp = (blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x) / kWarp;
  if (warp >= warps) return;
  const unsigned lane = threadIdx.x & (kWarp - 1);
  const unsigned lane_bit = 1u << lane;
  const size_t i = warp * kWarp + lane;
  const bool valid = i < count;

  Ray r;  // lanes past the end get an empty interval: traversal_begin marks them done at once
  r.tmax = 0.f;
  if (valid) r = load_ray(rays, Indirect ? order[i] : i);
  TraversalState st;
  traversal_begin(st, r);
  RayCounters rc;
  WarpStepCounters c;
  c.warps = 1;
  constexpr uint32_t kNodeBytes = sizeof(BvhNode), kTriBytes = sizeof(BvhTriangle);

  unsigned live = __ballot_sync(kFullMask, valid && !traversal_done(st));
  while (live) {
    // Node loop.
    unsigned n = __ballot_sync(kFullMask, (live & lane_bit) && traversal_wants_node(st));
    while (n) {
      const bool in_n = (n & lane_bit) != 0;
      const uint64_t addr = layout.node_base + uint64_t{kNodeBytes} * static_cast<uint32_t>(in_n ? st.node_ref : 0);
      c.node_steps += 1;
      c.node_lanes += static_cast<uint32_t>(__popc(n));
      c.node_lines += units_of(in_n, addr, kNodeBytes, layout.line_bytes);
      c.node_fetches += units_of(in_n, addr, kNodeBytes, layout.sector_bytes);
      if (in_n) node_step(st, bvh, rc);
      if (__ballot_sync(kFullMask, in_n && traversal_has_leaf(st)) == n) break;
      n = __ballot_sync(kFullMask, in_n && traversal_wants_node(st));
    }
    // Leaf loop.
    unsigned l = __ballot_sync(kFullMask, (live & lane_bit) && traversal_has_leaf(st));
    while (l) {
      const bool in_l = (l & lane_bit) != 0;
      const uint32_t first = in_l ? leaf_first(st.leaf_ref) : 0u;
      const uint32_t tri_count = in_l ? leaf_count(st.leaf_ref) : 0u;
      const uint32_t max_count = __reduce_max_sync(kFullMask, tri_count);
      c.leaf_steps += 1;
      c.leaf_lanes += static_cast<uint32_t>(__popc(l));
      for (uint32_t j = 0; j < max_count; ++j) {
        const bool in_sub = in_l && j < tri_count;
        const unsigned sub = __ballot_sync(kFullMask, in_sub);
        const uint64_t addr = layout.tri_base + uint64_t{kTriBytes} * (in_sub ? first + j : 0u);
        c.triangle_steps += 1;
        c.triangle_lanes += static_cast<uint32_t>(__popc(sub));
        c.triangle_lines += units_of(in_sub, addr, kTriBytes, layout.line_bytes);
        c.triangle_fetches += units_of(in_sub, addr, kTriBytes, layout.sector_bytes);
      }
      if (in_l) leaf_step(st, bvh, rc, filter);
      l = __ballot_sync(kFullMask, in_l && traversal_has_leaf(st));
    }
    live = __ballot_sync(kFullMask, valid && !traversal_done(st));
  }

  c.rays = static_cast<uint32_t>(__popc(__ballot_sync(kFullMask, valid)));
  c.nodes = __reduce_add_sync(kFullMask, rc.nodes);
  c.leaves = __reduce_add_sync(kFullMask, rc.leaves);
  c.triangles = __reduce_add_sync(kFullMask, rc.triangles);
  if (valid) store_hit(hits, i, st.hit);
  if (lane == 0) out[warp] = c;
}

void check_block(int block) {
  if (block < kWarp || block > 1024 || block % kWarp != 0)
    throw Error("cuda: block size " + std::to_string(block) + " is not a multiple of 32 in [32, 1024]");
}

unsigned grid_for(size_t threads, int block) {
  const size_t blocks = (threads + static_cast<size_t>(block) - 1) / static_cast<size_t>(block);
  if (blocks > 0x7fffffffu) throw Error("cuda: batch of " + std::to_string(threads) + " threads is too large");
  return static_cast<unsigned>(blocks);
}

template <class Filter>
void launch_counting(const BvhView& bvh, const Filter& filter, unsigned blocks, int block, const Ray* rays,
                     const uint32_t* order, size_t count, Hit* hits, const SimtConfig& layout, WarpStepCounters* out,
                     size_t warps) {
  if (order)
    counting_kernel<true><<<blocks, block>>>(bvh, filter, rays, order, count, hits, layout, out, warps);
  else
    counting_kernel<false><<<blocks, block>>>(bvh, filter, rays, nullptr, count, hits, layout, out, warps);
}

}  // namespace

struct DeviceTracer::Impl {
  DeviceBuffer<BvhNode> nodes;
  DeviceBuffer<CwbvhNode> cwbvh_nodes;  // the CWBVH layout's nodes (`nodes` then stays empty)
  DeviceBuffer<BvhTriangle> tris;
  uint32_t node_count = 0, tri_count = 0;
  bool cwbvh = false;
  // The scene's alpha MASK arrays (empty: no masks, and the kernels run NoAlphaTest).
  DeviceBuffer<uint32_t> alpha_tri_texture;
  DeviceBuffer<float> alpha_tri_uv;
  DeviceBuffer<AlphaTexture> alpha_textures;
  DeviceBuffer<uint8_t> alpha_texels;
  bool masked = false;
  DeviceBuffer<Ray> rays;
  DeviceBuffer<uint32_t> order;
  DeviceBuffer<Hit> hits;
  DeviceBuffer<unsigned long long> next_ray{1};
  DeviceBuffer<WarpStepCounters> warp_counters;
  EventTimer timer;
  float last_ms = -1.f;
  int sms = 0;

  void init(const BvhTriangle* host_tris, uint32_t triangles, uint32_t node_total, const AlphaMaskArrays& alpha) {
    if (!alpha.empty()) {
      const std::string error = alpha_arrays_error(alpha, host_tris, triangles);
      if (!error.empty()) throw Error("cuda: alpha MASK arrays: " + error);
      alpha_tri_texture.upload(alpha.tri_texture, alpha.tri_count);
      alpha_tri_uv.upload(alpha.tri_uv, 6 * alpha.tri_count);
      alpha_textures.upload(alpha.textures, alpha.texture_count);
      alpha_texels.upload(alpha.texels, alpha.texel_count);
      masked = true;
    }
    tris.upload(host_tris, triangles);
    node_count = node_total;
    tri_count = triangles;
    int device = 0;
    RAYCOH_CUDA_CHECK(cudaGetDevice(&device));
    RAYCOH_CUDA_CHECK(cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, device));
  }
  BvhView view() const { return BvhView{nodes.get(), tris.get(), node_count, tri_count}; }
  CwbvhView cwbvh_view() const { return CwbvhView{cwbvh_nodes.get(), tris.get(), node_count, tri_count}; }
  AlphaTest alpha_test() const {
    return AlphaTest{
        AlphaMaskView{alpha_tri_texture.get(), alpha_tri_uv.get(), alpha_textures.get(), alpha_texels.get()}};
  }

  // Resident blocks per SM of this layout's persistent kernel (the instance that trace_device launches).
  template <class View, class Filter>
  static int blocks_per_sm(int block) {
    int per_sm = 0;
    RAYCOH_CUDA_CHECK(
        cudaOccupancyMaxActiveBlocksPerMultiprocessor(&per_sm, persistent_kernel<false, View, Filter>, block, 0));
    return per_sm;
  }
  int persistent_blocks_per_sm(int block, Bvh2Traversal traversal) const {
    if (cwbvh)
      return masked ? blocks_per_sm<CwbvhView, AlphaTest>(block) : blocks_per_sm<CwbvhView, NoAlphaTest>(block);
    if (traversal == Bvh2Traversal::Tuned)
      return masked ? blocks_per_sm<WideBvhView, AlphaTest>(block) : blocks_per_sm<WideBvhView, NoAlphaTest>(block);
    return masked ? blocks_per_sm<BvhView, AlphaTest>(block) : blocks_per_sm<BvhView, NoAlphaTest>(block);
  }

  // Launches the chosen kernel between the timer's events; persistent_blocks: the resident blocks of the GPU.
  template <class View, class Filter>
  void launch(const View& bvh, const Filter& filter, const Ray* d_rays, const uint32_t* d_order, size_t count,
              Hit* d_hits, const TraceLaunch& launch, int persistent_blocks) {
    if (launch.kernel == TraceKernel::Persistent) {
      // Resident blocks only, and no more warps than the batch has: every warp fetches at least once.
      const unsigned blocks =
          std::min<unsigned>(static_cast<unsigned>(persistent_blocks), std::max(1u, grid_for(count, launch.block)));
      RAYCOH_CUDA_CHECK(cudaMemset(next_ray.get(), 0, sizeof(unsigned long long)));
      timer.start();
      if (d_order)
        persistent_kernel<true><<<blocks, launch.block>>>(bvh, filter, d_rays, d_order, count, d_hits, next_ray.get());
      else
        persistent_kernel<false><<<blocks, launch.block>>>(bvh, filter, d_rays, d_order, count, d_hits, next_ray.get());
      RAYCOH_CUDA_CHECK_LAUNCH();
      timer.stop();
    } else {
      const unsigned blocks = grid_for(count, launch.block);
      timer.start();
      if (blocks > 0) {
        if (d_order)
          simple_kernel<true><<<blocks, launch.block>>>(bvh, filter, d_rays, d_order, count, d_hits);
        else
          simple_kernel<false><<<blocks, launch.block>>>(bvh, filter, d_rays, d_order, count, d_hits);
        RAYCOH_CUDA_CHECK_LAUNCH();
      }
      timer.stop();
    }
  }
};

DeviceTracer::DeviceTracer(const BvhView& bvh, const AlphaMaskArrays& alpha) : impl_(std::make_unique<Impl>()) {
  impl_->nodes.upload(bvh.nodes, bvh.node_count);
  impl_->init(bvh.tris, bvh.tri_count, bvh.node_count, alpha);
}

DeviceTracer::DeviceTracer(const CwbvhView& bvh, const AlphaMaskArrays& alpha) : impl_(std::make_unique<Impl>()) {
  impl_->cwbvh = true;
  impl_->cwbvh_nodes.upload(bvh.nodes, bvh.node_count);
  impl_->init(bvh.tris, bvh.tri_count, bvh.node_count, alpha);
}

DeviceTracer::~DeviceTracer() = default;

float DeviceTracer::last_kernel_ms() const { return impl_->last_ms; }

bool DeviceTracer::alpha_masked() const { return impl_->masked; }

int DeviceTracer::persistent_blocks(int block, Bvh2Traversal traversal) const {
  check_block(block);
  return std::max(1, impl_->persistent_blocks_per_sm(block, traversal)) * std::max(1, impl_->sms);
}

void DeviceTracer::launch_device(const Ray* d_rays, const uint32_t* d_order, size_t count, Hit* d_hits,
                                 const TraceLaunch& launch) {
  check_block(launch.block);
  Impl& m = *impl_;
  const int blocks =
      launch.kernel == TraceKernel::Persistent ? persistent_blocks(launch.block, launch.traversal) : 0;
  const bool tuned = launch.traversal == Bvh2Traversal::Tuned;
  if (m.cwbvh && m.masked)
    m.launch(m.cwbvh_view(), m.alpha_test(), d_rays, d_order, count, d_hits, launch, blocks);
  else if (m.cwbvh)
    m.launch(m.cwbvh_view(), NoAlphaTest{}, d_rays, d_order, count, d_hits, launch, blocks);
  else if (m.masked && tuned)
    m.launch(WideBvhView{m.view()}, m.alpha_test(), d_rays, d_order, count, d_hits, launch, blocks);
  else if (tuned)
    m.launch(WideBvhView{m.view()}, NoAlphaTest{}, d_rays, d_order, count, d_hits, launch, blocks);
  else if (m.masked)
    m.launch(m.view(), m.alpha_test(), d_rays, d_order, count, d_hits, launch, blocks);
  else
    m.launch(m.view(), NoAlphaTest{}, d_rays, d_order, count, d_hits, launch, blocks);
}

float DeviceTracer::wait_kernel_ms() {
  impl_->last_ms = impl_->timer.elapsed_ms();  // synchronises: kernel faults surface here
  return impl_->last_ms;
}

float DeviceTracer::trace_device(const Ray* d_rays, const uint32_t* d_order, size_t count, Hit* d_hits,
                                 const TraceLaunch& launch) {
  launch_device(d_rays, d_order, count, d_hits, launch);
  return wait_kernel_ms();
}

void DeviceTracer::trace(const Ray* rays, const uint32_t* order, size_t count, Hit* hits, const TraceLaunch& launch) {
  Impl& m = *impl_;
  m.rays.upload(rays, count);
  if (order) m.order.upload(order, count);
  m.hits.reserve(count);
  trace_device(m.rays.get(), order ? m.order.get() : nullptr, count, m.hits.get(), launch);
  m.hits.download(hits, count);
}

void DeviceTracer::trace_counting(const Ray* rays, const uint32_t* order, size_t count, Hit* hits,
                                  const SimtConfig& layout, int block, std::vector<WarpStepCounters>& warps) {
  Impl& m = *impl_;
  m.rays.upload(rays, count);
  if (order) m.order.upload(order, count);
  m.hits.reserve(count);
  trace_counting_device(m.rays.get(), order ? m.order.get() : nullptr, count, m.hits.get(), layout, block, warps);
  m.hits.download(hits, count);
}

void DeviceTracer::trace_counting_device(const Ray* d_rays, const uint32_t* d_order, size_t count, Hit* d_hits,
                                         const SimtConfig& layout, int block, std::vector<WarpStepCounters>& warps) {
  check_block(block);
  Impl& m = *impl_;
  if (m.cwbvh) throw Error("cuda: the counting kernel traces the BVH2 only; there is none for CWBVH");
  const size_t warp_count = (count + kWarp - 1) / kWarp;
  m.warp_counters.zero(warp_count);
  const unsigned blocks = grid_for(warp_count * kWarp, block);
  const BvhView bvh = m.view();
  m.timer.start();
  if (blocks > 0) {
    if (m.masked)
      launch_counting(bvh, m.alpha_test(), blocks, block, d_rays, d_order, count, d_hits, layout, m.warp_counters.get(),
                      warp_count);
    else
      launch_counting(bvh, NoAlphaTest{}, blocks, block, d_rays, d_order, count, d_hits, layout, m.warp_counters.get(),
                      warp_count);
    RAYCOH_CUDA_CHECK_LAUNCH();
  }
  m.timer.stop();
  m.last_ms = m.timer.elapsed_ms();
  warps.resize(warp_count);
  m.warp_counters.download(warps.data(), warp_count);
}

}  // namespace raycoh::cuda
