// The device pipeline's own buffers, gather kernel and stage timers (cuda/device_stages.h).
// (No fmt here: its consteval format strings do not compile under nvcc 13.)
#include <cuda_runtime.h>

#include "core/error.h"
#include "cuda/cuda_check.cuh"
#include "cuda/device_common.cuh"
#include "cuda/device_stages.h"

namespace raycoh::cuda {

namespace {

// One thread per slot of the permuted batch; the group arrays only where the batch has them.
__global__ void gather_batch_kernel(BatchView in, const uint32_t* order, size_t n, BatchView out) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  const uint32_t j = order[i];
  const float4* src = reinterpret_cast<const float4*>(in.rays + j);  // rays as two 16-byte words
  float4* dst = reinterpret_cast<float4*>(out.rays + i);
  dst[0] = __ldg(src);
  dst[1] = __ldg(src + 1);
  out.pixel[i] = in.pixel[j];
  out.pdf[i] = in.pdf[j];
  out.weight[i] = in.weight[j];
  out.normal[i] = in.normal[j];
  out.material[i] = in.material[j];
  if (in.tile) {
    out.tile[i] = in.tile[j];
    out.group[i] = in.group[j];
    out.group_type[i] = in.group_type[j];
  }
}

}  // namespace

struct DeviceStages::Impl {
  DeviceBuffer<Ray> primary_rays;
  DeviceBuffer<uint32_t> primary_pixels;
  int width = 0, height = 0;
  uint32_t frame = 0;
  size_t primary_count = 0;
  // The permuted batch.
  DeviceBuffer<Ray> rays;
  DeviceBuffer<uint32_t> pixel;
  DeviceBuffer<float> pdf;
  DeviceBuffer<Vec3> weight, normal;
  DeviceBuffer<MaterialClass> material;
  DeviceBuffer<uint32_t> tile, group;
  DeviceBuffer<GroupType> group_type;
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
  m.rays.reserve(n);
  m.pixel.reserve(n);
  m.pdf.reserve(n);
  m.weight.reserve(n);
  m.normal.reserve(n);
  m.material.reserve(n);
  if (m.grouped) {
    m.tile.reserve(n);
    m.group.reserve(n);
    m.group_type.reserve(n);
  }
  const BatchView out{m.rays.get(),
                      m.pixel.get(),
                      m.pdf.get(),
                      m.weight.get(),
                      m.normal.get(),
                      m.material.get(),
                      m.grouped ? m.tile.get() : nullptr,
                      m.grouped ? m.group.get() : nullptr,
                      m.grouped ? m.group_type.get() : nullptr};
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
  const Impl& m = *impl_;
  out.resize(n, m.grouped);
  m.rays.download(out.rays.data(), n);
  m.pixel.download(out.pixel.data(), n);
  m.pdf.download(out.pdf.data(), n);
  m.weight.download(out.weight.data(), n);
  m.normal.download(out.normal.data(), n);
  m.material.download(out.material.data(), n);
  if (m.grouped) {
    m.tile.download(out.tile.data(), n);
    m.group.download(out.group.data(), n);
    m.group_type.download(out.group_type.data(), n);
  }
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
