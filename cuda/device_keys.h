// Host API of the reordering step on the GPU (implemented in cuda/device_keys.cu): sort keys of every key encoder
// with the host/device code functions of encoders/keys.h, CUB's radix sort of (key, index) pairs over exactly the
// key's bits, and the physical gather of the rays, each stage timed with CUDA events. Plain C++ (g++-includable).
//
// Keys equal the CPU encoders' keys bit for bit for origin, aila, twopoint and mlhcc (IEEE +, -, x, / and integer
// work only). reis and costa use atan2f / acosf, where CUDA and glibc may differ by an ulp, which moves a key
// only when phi or theta lies within that ulp of a quantisation boundary (encoders/keys.h): the tests bound how
// many keys that touches. cub::DeviceRadixSort::SortPairs is a stable LSD radix sort like encoders/radix_sort.h,
// so the same keys give the same order. MLHCC's cuts are built on the host (build_mlhcc_cuts) and uploaded with
// the BVH nodes when the encoder is made.
//
// The device pipeline (cuda/device_pipeline.h: a `cuda` run with pipeline=device) sorts with sort_device() on the
// batch it generated on the device; the gpu tests (tests/gpu_keys_test.cpp) check that the GPU keys and order
// equal the CPU's.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "core/ray.h"
#include "core/vec.h"
#include "encoders/key_recipe.h"

namespace raycoh {
struct Bvh;
}

namespace raycoh::cuda {

struct GpuReorderTimings {
  float key_ms = 0.f, sort_ms = 0.f, permute_ms = 0.f;  // CUDA events
};

// One encoder on the device: its tables (MLHCC cuts and BVH nodes) uploaded once, buffers grown on demand.
class DeviceKeys {
 public:
  // recipe: Encoder::recipe() of the CPU encoder. bvh: needed by mlhcc (it must outlive the constructor call
  // only; the cuts are copied to the device). Throws raycoh::Error for kind None (no keys) and mlhcc without bvh.
  DeviceKeys(const KeyRecipe& recipe, const Bvh* bvh);
  ~DeviceKeys();
  DeviceKeys(const DeviceKeys&) = delete;
  DeviceKeys& operator=(const DeviceKeys&) = delete;

  int key_bits() const;
  // keys[i] = the key of rays[i] (uploads the rays, downloads the keys).
  void keys(const Ray* rays, size_t n, uint64_t* keys);
  // Stable sort of (keys[i], i) by the low key_bits() bits: sorted_keys and order (both n long, downloaded).
  void sort(const uint64_t* keys, size_t n, uint64_t* sorted_keys, uint32_t* order);
  // The whole step on the device: keys, sort, and (sorted_rays not null) the gather sorted_rays[i] =
  // rays[order[i]]; outputs downloaded, each stage timed (transfers excluded).
  void reorder(const Ray* rays, size_t n, uint64_t* sorted_keys, uint32_t* order, Ray* sorted_rays,
               GpuReorderTimings& timings);
  // Keys and sort of n rays that live on the device, queued on the default stream between the key and sort
  // timers' events (nothing is waited for): the order and sorted keys stay on the device, valid until the next
  // call (keys of at most 32 bits are made and sorted as 32-bit words). wait_timings() waits and returns key_ms and
  // sort_ms (permute_ms 0: the caller gathers).
  void sort_device(const Ray* d_rays, size_t n);
  const uint32_t* device_order() const;
  GpuReorderTimings wait_timings() const;
  // The first n entries of device_order() (waits for the sort).
  void download_order(uint32_t* order, size_t n) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace raycoh::cuda
