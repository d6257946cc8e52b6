// Sort keys, CUB radix sort and ray gather on the GPU (see cuda/device_keys.h). One thread per ray runs the same
// encoders/keys.h code function the CPU encoder runs (origin_code, reis_code, costa_code, aila_code,
// twopoint_code, mlhcc_code) and keeps the top `bits` bits; cub::DeviceRadixSort::SortPairs sorts (key, index)
// pairs over bits [0, bits) only, which is what encoders/radix_sort.h does on the CPU (Merrill & Grimshaw,
// "High Performance and Scalable Radix Sorting", 2011, is CUB's onesweep predecessor; stable LSD either way).
// (No fmt here: its consteval format strings do not compile under nvcc 13.)
#include <cuda_runtime.h>

#include <cub/device/device_radix_sort.cuh>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "cuda/cuda_check.cuh"
#include "cuda/device_keys.h"
#include "encoders/keys.h"
#include "encoders/mlhcc_cuts.h"

namespace raycoh::cuda {

namespace {

struct KeyParams {
  int bits;
  Bounds box;
  float length_factor;
  bool with_end;
  MlhccCuts cuts;  // device pointers (mlhcc only)
};

template <KeyKind Kind>
__device__ __forceinline__ uint64_t code_of(const KeyParams& kp, const Ray& r) {
  if constexpr (Kind == KeyKind::Origin) return origin_code(r.org, kp.box);
  if constexpr (Kind == KeyKind::Reis) return reis_code(r.org, r.dir, kp.box);
  if constexpr (Kind == KeyKind::Costa) return costa_code(r.org, r.dir, kp.box);
  if constexpr (Kind == KeyKind::Aila) return aila_code(r.org, r.dir, kp.box);
  if constexpr (Kind == KeyKind::TwoPoint) return twopoint_code(r.org, r.dir, r.tmax, kp.box, kp.length_factor);
  if constexpr (Kind == KeyKind::Mlhcc)
    return mlhcc_code(r.org, r.dir, r.tmax, kp.box, kp.length_factor, kp.cuts, kp.with_end, kp.bits);
  return 0;
}

template <KeyKind Kind>
__global__ void key_kernel(KeyParams kp, const Ray* rays, size_t n, uint64_t* keys) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (i < n) keys[i] = key_from_code(code_of<Kind>(kp, rays[i]), kp.bits);
}

__global__ void iota_kernel(uint32_t* v, size_t n) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (i < n) v[i] = static_cast<uint32_t>(i);
}

__global__ void gather_kernel(const Ray* in, const uint32_t* order, size_t n, Ray* out) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (i < n) out[i] = in[order[i]];
}

constexpr int kBlock = 256;

unsigned blocks_for(size_t n) {
  const size_t blocks = (n + kBlock - 1) / kBlock;
  if (blocks > 0x7fffffffu) throw Error("cuda: " + std::to_string(n) + " rays are too many for one launch");
  return static_cast<unsigned>(blocks);
}

}  // namespace

struct DeviceKeys::Impl {
  KeyRecipe config;
  KeyParams params{};
  DeviceBuffer<BvhNode> nodes;
  DeviceBuffer<MlhccNodeCut> cuts;
  DeviceBuffer<Ray> rays, sorted_rays;
  DeviceBuffer<uint64_t> keys, sorted_keys;
  DeviceBuffer<uint32_t> values, order;
  DeviceBuffer<unsigned char> sort_temp;
  EventTimer key_timer, sort_timer, permute_timer;

  void launch_keys(const Ray* d_rays, size_t n, uint64_t* d_keys) {
    if (n == 0) return;
    const unsigned blocks = blocks_for(n);
    switch (config.kind) {
      case KeyKind::None:
        return;
      case KeyKind::Origin:
        key_kernel<KeyKind::Origin><<<blocks, kBlock>>>(params, d_rays, n, d_keys);
        break;
      case KeyKind::Reis:
        key_kernel<KeyKind::Reis><<<blocks, kBlock>>>(params, d_rays, n, d_keys);
        break;
      case KeyKind::Costa:
        key_kernel<KeyKind::Costa><<<blocks, kBlock>>>(params, d_rays, n, d_keys);
        break;
      case KeyKind::Aila:
        key_kernel<KeyKind::Aila><<<blocks, kBlock>>>(params, d_rays, n, d_keys);
        break;
      case KeyKind::TwoPoint:
        key_kernel<KeyKind::TwoPoint><<<blocks, kBlock>>>(params, d_rays, n, d_keys);
        break;
      case KeyKind::Mlhcc:
        key_kernel<KeyKind::Mlhcc><<<blocks, kBlock>>>(params, d_rays, n, d_keys);
        break;
    }
    RAYCOH_CUDA_CHECK_LAUNCH();
  }

  // Sorts (keys, 0..n-1) by the key bits into sorted_keys / order.
  void launch_sort(size_t n) {
    if (n == 0) return;
    if (n > 0x7fffffffu) throw Error("cuda: radix sort of " + std::to_string(n) + " pairs is too large");
    iota_kernel<<<blocks_for(n), kBlock>>>(values.get(), n);
    RAYCOH_CUDA_CHECK_LAUNCH();
    size_t bytes = 0;
    RAYCOH_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(nullptr, bytes, keys.get(), sorted_keys.get(), values.get(),
                                                      order.get(), static_cast<int>(n), 0, config.bits));
    sort_temp.reserve(bytes);
    RAYCOH_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(sort_temp.get(), bytes, keys.get(), sorted_keys.get(),
                                                      values.get(), order.get(), static_cast<int>(n), 0, config.bits));
  }

  // The key and sort buffers (the host-array calls upload their rays into `rays` themselves; sort_device reads the
  // caller's device rays and needs none).
  void reserve(size_t n) {
    keys.reserve(n);
    sorted_keys.reserve(n);
    values.reserve(n);
    order.reserve(n);
  }
};

DeviceKeys::DeviceKeys(const KeyRecipe& config, const Bvh* bvh) : impl_(std::make_unique<Impl>()) {
  if (config.kind == KeyKind::None)
    throw Error("encoder 'none' makes no keys; GPU encoders: origin, reis, costa, aila, twopoint, mlhcc");
  Impl& m = *impl_;
  m.config = config;
  m.params.bits = config.bits;
  m.params.box = config.box;
  m.params.length_factor = config.length_factor;
  m.params.with_end = config.with_end;
  if (config.kind == KeyKind::Mlhcc) {
    if (!bvh) throw Error("encoder 'mlhcc' (GPU): needs the scene's BVH, and none was given");
    const MlhccCutTable table =
        build_mlhcc_cuts(*bvh, config.lambda, config.global_ranks ? MlhccRanks::Global : MlhccRanks::Compressed);
    m.nodes.upload(bvh->nodes.data(), bvh->nodes.size());
    m.cuts.upload(table.cuts.data(), table.cuts.size());
    m.params.cuts = table.view();
    m.params.cuts.nodes = m.nodes.get();
    m.params.cuts.cuts = m.cuts.get();
  }
}

DeviceKeys::~DeviceKeys() = default;

int DeviceKeys::key_bits() const { return impl_->config.bits; }

void DeviceKeys::keys(const Ray* rays, size_t n, uint64_t* keys) {
  Impl& m = *impl_;
  m.reserve(n);
  m.rays.upload(rays, n);
  m.launch_keys(m.rays.get(), n, m.keys.get());
  m.keys.download(keys, n);
}

void DeviceKeys::sort(const uint64_t* keys, size_t n, uint64_t* sorted_keys, uint32_t* order) {
  Impl& m = *impl_;
  m.reserve(n);
  m.keys.upload(keys, n);
  m.launch_sort(n);
  m.sorted_keys.download(sorted_keys, n);
  m.order.download(order, n);
}

void DeviceKeys::sort_device(const Ray* d_rays, size_t n) {
  Impl& m = *impl_;
  m.reserve(n);
  m.key_timer.start();
  m.launch_keys(d_rays, n, m.keys.get());
  m.key_timer.stop();
  m.sort_timer.start();
  m.launch_sort(n);
  m.sort_timer.stop();
}

const uint32_t* DeviceKeys::device_order() const { return impl_->order.get(); }

const uint64_t* DeviceKeys::device_sorted_keys() const { return impl_->sorted_keys.get(); }

void DeviceKeys::download_order(uint32_t* order, size_t n) const { impl_->order.download(order, n); }

GpuReorderTimings DeviceKeys::wait_timings() const {
  GpuReorderTimings t;
  t.key_ms = impl_->key_timer.elapsed_ms();
  t.sort_ms = impl_->sort_timer.elapsed_ms();
  return t;
}

void DeviceKeys::reorder(const Ray* rays, size_t n, uint64_t* sorted_keys, uint32_t* order, Ray* sorted_rays,
                         GpuReorderTimings& timings) {
  Impl& m = *impl_;
  m.reserve(n);
  if (sorted_rays) m.sorted_rays.reserve(n);
  m.rays.upload(rays, n);
  sort_device(m.rays.get(), n);
  m.permute_timer.start();
  if (sorted_rays && n > 0) {
    gather_kernel<<<blocks_for(n), kBlock>>>(m.rays.get(), m.order.get(), n, m.sorted_rays.get());
    RAYCOH_CUDA_CHECK_LAUNCH();
  }
  m.permute_timer.stop();
  timings = wait_timings();
  const float permute_ms = m.permute_timer.elapsed_ms();
  timings.permute_ms = sorted_rays ? permute_ms : 0.f;
  m.sorted_keys.download(sorted_keys, n);
  m.order.download(order, n);
  if (sorted_rays) m.sorted_rays.download(sorted_rays, n);
}

}  // namespace raycoh::cuda
