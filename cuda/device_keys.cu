// Sort keys, CUB radix sort and ray gather on the GPU (see cuda/device_keys.h). One thread per ray runs the
// recipe's key function, key_code<Kind> of encoders/key_code.h, the one the CPU encoder runs, and keeps the top
// `bits` bits; cub::DeviceRadixSort::SortPairs sorts (key, index)
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
#include "encoders/key_recipe.h"
#include "encoders/keys.h"
#include "encoders/mlhcc_cuts.h"

namespace raycoh::cuda {

namespace {

// K: uint32_t for keys of at most 32 bits (half the bytes for the key kernel and every sort pass), else uint64_t.
// The code is the recipe's key function (encoders/key_code.h), the one the CPU encoder runs.
template <KeyKind Kind, class K>
__global__ void key_kernel(KeyArgs args, const Ray* rays, size_t n, K* keys) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (i < n) keys[i] = static_cast<K>(key_from_code(key_code<Kind>(args, rays[i]), args.bits));
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
  KeyArgs params{};
  DeviceBuffer<BvhNode> nodes;
  DeviceBuffer<MlhccNodeCut> cuts;
  DeviceBuffer<Ray> rays, sorted_rays;
  DeviceBuffer<uint64_t> keys, sorted_keys;
  DeviceBuffer<uint32_t> keys32, sorted_keys32;
  DeviceBuffer<uint32_t> values, order;
  size_t iota_count = 0;  // values[i] = i for i < iota_count
  DeviceBuffer<unsigned char> sort_temp;
  EventTimer key_timer, sort_timer, permute_timer;

  // Keys of at most 32 bits are sorted as 32-bit words (keys32 / sorted_keys32), wider ones as 64-bit words.
  bool narrow() const { return config.bits <= 32; }

  template <class K>
  void launch_keys_as(const Ray* d_rays, size_t n, K* d_keys) {
    const unsigned blocks = blocks_for(n);
    with_key_kind(config.kind,
                  [&](auto kind) { key_kernel<decltype(kind)::value><<<blocks, kBlock>>>(params, d_rays, n, d_keys); });
    RAYCOH_CUDA_CHECK_LAUNCH();
  }
  void launch_keys(const Ray* d_rays, size_t n) {
    if (n == 0) return;
    if (narrow())
      launch_keys_as(d_rays, n, keys32.get());
    else
      launch_keys_as(d_rays, n, keys.get());
  }

  // Sorts (keys, 0..n-1) by the key's bits [0, bits) into sorted keys / order. The index column 0..n-1 is written
  // once per size (CUB reads it and leaves it unchanged).
  template <class K>
  void sort_pairs(const K* in, K* out, size_t n) {
    size_t bytes = 0;
    RAYCOH_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(nullptr, bytes, in, out, values.get(), order.get(),
                                                      static_cast<int>(n), 0, config.bits));
    sort_temp.reserve(bytes);
    RAYCOH_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(sort_temp.get(), bytes, in, out, values.get(), order.get(),
                                                      static_cast<int>(n), 0, config.bits));
  }
  void launch_sort(size_t n) {
    if (n == 0) return;
    if (n > 0x7fffffffu) throw Error("cuda: radix sort of " + std::to_string(n) + " pairs is too large");
    if (iota_count < n) {
      iota_kernel<<<blocks_for(n), kBlock>>>(values.get(), n);
      RAYCOH_CUDA_CHECK_LAUNCH();
      iota_count = n;
    }
    if (narrow())
      sort_pairs(keys32.get(), sorted_keys32.get(), n);
    else
      sort_pairs(keys.get(), sorted_keys.get(), n);
  }

  // The first n keys of `wide` (keys of more than 32 bits) or `narrow`, as 64-bit words.
  void download_widened(const DeviceBuffer<uint64_t>& wide, const DeviceBuffer<uint32_t>& narrow_buffer, uint64_t* out,
                        size_t n) const {
    if (!narrow()) {
      wide.download(out, n);
      return;
    }
    std::vector<uint32_t> words(n);
    narrow_buffer.download(words.data(), n);
    for (size_t i = 0; i < n; ++i) out[i] = words[i];
  }

  // The key and sort buffers (the host-array calls upload their rays into `rays` themselves; sort_device reads the
  // caller's device rays and needs none).
  void reserve(size_t n) {
    if (narrow()) {
      keys32.reserve(n);
      sorted_keys32.reserve(n);
    } else {
      keys.reserve(n);
      sorted_keys.reserve(n);
    }
    if (values.capacity() < n) iota_count = 0;  // a new buffer: its index column is written again
    values.reserve(n);
    order.reserve(n);
  }
};

DeviceKeys::DeviceKeys(const KeyRecipe& config, const Bvh* bvh) : impl_(std::make_unique<Impl>()) {
  if (config.kind == KeyKind::None) throw Error("encoder 'none' makes no keys; GPU encoders: " + key_kind_names());
  Impl& m = *impl_;
  m.config = config;
  m.params = key_args(config);
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
  m.launch_keys(m.rays.get(), n);
  m.download_widened(m.keys, m.keys32, keys, n);
}

void DeviceKeys::sort(const uint64_t* keys, size_t n, uint64_t* sorted_keys, uint32_t* order) {
  Impl& m = *impl_;
  m.reserve(n);
  if (m.narrow()) {
    std::vector<uint32_t> narrow_keys(keys, keys + n);
    m.keys32.upload(narrow_keys.data(), n);
  } else {
    m.keys.upload(keys, n);
  }
  m.launch_sort(n);
  m.download_widened(m.sorted_keys, m.sorted_keys32, sorted_keys, n);
  m.order.download(order, n);
}

void DeviceKeys::sort_device(const Ray* d_rays, size_t n) {
  Impl& m = *impl_;
  m.reserve(n);
  m.key_timer.start();
  m.launch_keys(d_rays, n);
  m.key_timer.stop();
  m.sort_timer.start();
  m.launch_sort(n);
  m.sort_timer.stop();
}

const uint32_t* DeviceKeys::device_order() const { return impl_->order.get(); }

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
  m.download_widened(m.sorted_keys, m.sorted_keys32, sorted_keys, n);
  m.order.download(order, n);
  if (sorted_rays) m.sorted_rays.download(sorted_rays, n);
}

}  // namespace raycoh::cuda
