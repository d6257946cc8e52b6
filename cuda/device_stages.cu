// The device pipeline's own buffers, gather kernel and stage timers (cuda/device_stages.h).
// (No fmt here: its consteval format strings do not compile under nvcc 13.)
#include <cuda_runtime.h>

#include "core/error.h"
#include "cuda/cuda_check.cuh"
#include "cuda/device_batch.cuh"
#include "cuda/device_common.cuh"
#include "cuda/device_stages.h"

namespace raycoh::cuda {

namespace {

// One thread per slot of the permuted batch; the group columns only where the batch has them.
__global__ void gather_batch_kernel(BatchView in, const uint32_t* order, size_t n, BatchView out) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (i < n) gather_columns(in, order[i], i, out);
}

}  // namespace

struct DeviceStages::Impl {
  DeviceBuffer<Ray> primary_rays;
  DeviceBuffer<uint32_t> primary_pixels;
  int width = 0, height = 0;
  uint32_t frame = 0;
  size_t primary_count = 0;
  DeviceBatch permuted;
  bool grouped = false;
  DeviceBuffer<Hit> hits;
  EventTimer primary_timer, permute_timer, span_timer;
};

DeviceStages::DeviceStages() : impl_(std::make_unique<Impl>()) {}

DeviceStages::~DeviceStages() = default;

void DeviceStages::launch_primary(const Camera& camera, int width, int height, int tile_w, int tile_h, uint32_t seed,
                                  uint32_t frame, bool jitter) {
  Impl& m = *impl_;
  if (width < 1 || height < 1) throw Error("cuda: primary rays need a positive resolution");
  const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
  m.primary_rays.reserve(n);
  m.primary_pixels.reserve(n);
  m.primary_timer.start();
  launch_primary_rays(camera, width, height, RayOrder::Tile, tile_w, tile_h, seed, frame, jitter, m.primary_rays.get(),
                      m.primary_pixels.get());
  m.primary_timer.stop();
  m.width = width;
  m.height = height;
  m.frame = frame;
  m.primary_count = n;
}

const Ray* DeviceStages::primary_rays() const { return impl_->primary_rays.get(); }
const uint32_t* DeviceStages::primary_pixels() const { return impl_->primary_pixels.get(); }

size_t DeviceStages::primary_count() const { return impl_->primary_count; }

float DeviceStages::wait_primary_ms() const { return impl_->primary_timer.elapsed_ms(); }

void DeviceStages::download_primary(PixelRays& out) const {
  const Impl& m = *impl_;
  out.width = m.width;
  out.height = m.height;
  out.frame = m.frame;
  out.rays.resize(m.primary_count);
  out.pixel.resize(m.primary_count);
  m.primary_rays.download(out.rays.data(), m.primary_count);
  m.primary_pixels.download(out.pixel.data(), m.primary_count);
}

BatchView DeviceStages::launch_gather(const BatchView& in, const uint32_t* d_order, size_t n) {
  Impl& m = *impl_;
  m.grouped = in.tile != nullptr;
  const BatchView out = m.permuted.reserve(n, m.grouped);
  m.permute_timer.start();
  if (n > 0) {
    gather_batch_kernel<<<blocks_for(n, 256), 256>>>(in, d_order, n, out);
    RAYCOH_CUDA_CHECK_LAUNCH();
  }
  m.permute_timer.stop();
  return out;
}

float DeviceStages::wait_permute_ms() const { return impl_->permute_timer.elapsed_ms(); }

void DeviceStages::download_permuted(RayBatch& out, size_t n) const {
  impl_->permuted.download(out, n, impl_->grouped);
}

Hit* DeviceStages::hits(size_t n) {
  impl_->hits.reserve(n);
  return impl_->hits.get();
}

void DeviceStages::download_hits(std::vector<Hit>& out, size_t n) const {
  out.resize(n);
  impl_->hits.download(out.data(), n);
}

void DeviceStages::start_span() { impl_->span_timer.start(); }

void DeviceStages::stop_span() { impl_->span_timer.stop(); }

float DeviceStages::wait_span_ms() const { return impl_->span_timer.elapsed_ms(); }

}  // namespace raycoh::cuda
