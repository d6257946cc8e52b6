// The GPU traversal kernels behind cuda/trace_kernels.h: persistent-thread and one-thread-per-ray closest-hit
// kernels over the BVH2 (tuned and classic) and the CWBVH (stack in local or shared memory).
//
// Persistent threads follow Aila & Laine ("Understanding the Efficiency of Ray Traversal on GPUs", HPG 2009,
// section 3): launch only as many warps as the GPU holds at once; lane 0 of a warp takes 32 ray indices with one
// atomicAdd on a global counter and broadcasts the base with __shfl_sync, every lane traces its ray with the
// while-while loop of core/traverse.h, and the warp fetches again. Fetching whole warps of consecutive rays keeps
// the batch order's warp composition (docs/design.md section 1), which is what the generators and encoders shape.
//
// The warp-synchronous counting kernel that reproduces simt/simt.h is cuda/counting_kernel.cu.
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
#include "cuda/counting_kernel.h"
#include "cuda/cuda_check.cuh"
#include "cuda/ray_io.cuh"
#include "cuda/trace_kernels.h"
#include "cuda/trace_ray.cuh"

namespace raycoh::cuda {

namespace {

constexpr unsigned kFullMask = 0xffffffffu;
constexpr int kWarp = 32;

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

void check_block(int block) {
  if (block < kWarp || block > 1024 || block % kWarp != 0)
    throw Error("cuda: block size " + std::to_string(block) + " is not a multiple of 32 in [32, 1024]");
}

unsigned grid_for(size_t threads, int block) {
  const size_t blocks = (threads + static_cast<size_t>(block) - 1) / static_cast<size_t>(block);
  if (blocks > 0x7fffffffu) throw Error("cuda: batch of " + std::to_string(threads) + " threads is too large");
  return static_cast<unsigned>(blocks);
}

}  // namespace

struct DeviceTracer::Impl {
  DeviceBuffer<BvhNode> nodes;
  DeviceBuffer<CwbvhNode> cwbvh_nodes;  // the CWBVH layout's nodes (`nodes` then stays empty)
  DeviceBuffer<BvhTriangle> tris;
  uint32_t node_count = 0, tri_count = 0;
  bool cwbvh = false;
  uint32_t stack_entries = 0;  // CWBVH: stack entries a ray can need (the tree's depth + 2), for stack=shared
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

  // Dynamic shared memory of a block of the launch (the CWBVH stack with stack=shared, else none).
  size_t shared_bytes(const TraceLaunch& launch) const {
    return cwbvh && launch.shared_stack ? size_t{stack_entries} * sizeof(uint64_t) * static_cast<size_t>(launch.block)
                                        : 0;
  }

  // Resident blocks per SM of this layout's persistent kernel (the instance that trace_device launches).
  template <class View, class Filter>
  static int blocks_per_sm(int block, size_t shared = 0) {
    int per_sm = 0;
    RAYCOH_CUDA_CHECK(
        cudaOccupancyMaxActiveBlocksPerMultiprocessor(&per_sm, persistent_kernel<false, View, Filter>, block, shared));
    return per_sm;
  }
  int persistent_blocks_per_sm(const TraceLaunch& launch) const {
    const int block = launch.block;
    const Bvh2Traversal traversal = launch.traversal;
    if (cwbvh && launch.shared_stack)
      return masked ? blocks_per_sm<SharedStackCwbvhView, AlphaTest>(block, shared_bytes(launch))
                    : blocks_per_sm<SharedStackCwbvhView, NoAlphaTest>(block, shared_bytes(launch));
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
    const size_t shared = shared_bytes(launch);
    if (launch.kernel == TraceKernel::Persistent) {
      // Resident blocks only, and no more warps than the batch has: every warp fetches at least once.
      const unsigned blocks =
          std::min<unsigned>(static_cast<unsigned>(persistent_blocks), std::max(1u, grid_for(count, launch.block)));
      RAYCOH_CUDA_CHECK(cudaMemset(next_ray.get(), 0, sizeof(unsigned long long)));
      timer.start();
      if (d_order)
        persistent_kernel<true>
            <<<blocks, launch.block, shared>>>(bvh, filter, d_rays, d_order, count, d_hits, next_ray.get());
      else
        persistent_kernel<false>
            <<<blocks, launch.block, shared>>>(bvh, filter, d_rays, d_order, count, d_hits, next_ray.get());
      RAYCOH_CUDA_CHECK_LAUNCH();
      timer.stop();
    } else {
      const unsigned blocks = grid_for(count, launch.block);
      timer.start();
      if (blocks > 0) {
        if (d_order)
          simple_kernel<true><<<blocks, launch.block, shared>>>(bvh, filter, d_rays, d_order, count, d_hits);
        else
          simple_kernel<false><<<blocks, launch.block, shared>>>(bvh, filter, d_rays, d_order, count, d_hits);
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

DeviceTracer::DeviceTracer(const CwbvhView& bvh, const AlphaMaskArrays& alpha, uint32_t depth)
    : impl_(std::make_unique<Impl>()) {
  impl_->cwbvh = true;
  impl_->stack_entries = std::min<uint32_t>(depth + 2, kTraversalStackSize);
  impl_->cwbvh_nodes.upload(bvh.nodes, bvh.node_count);
  impl_->init(bvh.tris, bvh.tri_count, bvh.node_count, alpha);
}

DeviceTracer::~DeviceTracer() = default;

float DeviceTracer::last_kernel_ms() const { return impl_->last_ms; }

bool DeviceTracer::alpha_masked() const { return impl_->masked; }

DeviceScene DeviceTracer::device_scene() const {
  const Impl& m = *impl_;
  DeviceScene s;
  if (m.cwbvh)
    s.cwbvh = m.cwbvh_view();
  else
    s.bvh = m.view();
  s.cwbvh_layout = m.cwbvh;
  s.masked = m.masked;
  if (m.masked) s.alpha = m.alpha_test().view;
  return s;
}

int DeviceTracer::persistent_blocks(const TraceLaunch& launch) const {
  check_block(launch.block);
  return std::max(1, impl_->persistent_blocks_per_sm(launch)) * std::max(1, impl_->sms);
}

void DeviceTracer::check_launch(const TraceLaunch& launch) const {
  check_block(launch.block);
  const std::string choice = launch_choice_error(launch, impl_->cwbvh);
  if (!choice.empty()) throw Error("cuda: " + choice);
  const size_t shared = impl_->shared_bytes(launch);
  if (shared > 48 * 1024)
    throw Error("cuda: stack=shared needs " + std::to_string(shared) + " bytes of shared memory per block of " +
                std::to_string(launch.block) + " threads (" + std::to_string(impl_->stack_entries) +
                " entries of 8 bytes each), over the 49152 a block gets without opt-in; use a smaller block or "
                "stack=local");
}

void DeviceTracer::launch_device(const Ray* d_rays, const uint32_t* d_order, size_t count, Hit* d_hits,
                                 const TraceLaunch& launch) {
  check_launch(launch);
  Impl& m = *impl_;
  const int blocks = launch.kernel == TraceKernel::Persistent ? persistent_blocks(launch) : 0;
  const bool tuned = launch.traversal == Bvh2Traversal::Tuned;
  if (m.cwbvh && launch.shared_stack && m.masked)
    m.launch(SharedStackCwbvhView{m.cwbvh_view()}, m.alpha_test(), d_rays, d_order, count, d_hits, launch, blocks);
  else if (m.cwbvh && launch.shared_stack)
    m.launch(SharedStackCwbvhView{m.cwbvh_view()}, NoAlphaTest{}, d_rays, d_order, count, d_hits, launch, blocks);
  else if (m.cwbvh && m.masked)
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
