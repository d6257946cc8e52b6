// Primary rays on the GPU (cuda/device_generators.h): one thread per pixel computes the pixel's slot in the batch
// order and its camera ray with the shared host/device functions (core/tile_grid.h tile_major_slot,
// generators/primary_ray.h primary_ray) that make_primary_rays and make_pixel_order use on the CPU.
#include <cuda_runtime.h>

#include "cuda/cuda_check.cuh"
#include "cuda/device_common.cuh"
#include "cuda/device_generators.h"
#include "generators/primary_ray.h"

namespace raycoh::cuda {

namespace {

__global__ void primary_kernel(PinholeCamera camera, TileGrid grid, bool tile_order, uint32_t seed, uint32_t frame,
                               bool jitter, Ray* rays, uint32_t* pixels) {
  const size_t n = static_cast<size_t>(camera.width) * static_cast<size_t>(camera.height);
  const size_t index = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (index >= n) return;
  const auto p = static_cast<uint32_t>(index);
  const auto width = static_cast<uint32_t>(camera.width);
  const size_t slot = tile_order ? grid.tile_major_slot(static_cast<int>(p % width), static_cast<int>(p / width)) : p;
  rays[slot] = primary_ray(camera, p, seed, frame, jitter);
  pixels[slot] = p;
}

__global__ void sincos_kernel(const float* u, size_t n, float* s, float* c) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (i < n) sincos_turns(u[i], s[i], c[i]);
}

}  // namespace

void launch_primary_rays(const Camera& camera, int width, int height, RayOrder order, int tile_w, int tile_h,
                         uint32_t seed, uint32_t frame, bool jitter, Ray* d_rays, uint32_t* d_pixels) {
  if (width < 1 || height < 1 || tile_w < 1 || tile_h < 1)
    throw Error("cuda: primary rays need a positive resolution and tile size");
  const PinholeCamera pinhole = make_pinhole_camera(camera, width, height);
  const TileGrid grid(width, height, tile_w, tile_h);
  const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
  primary_kernel<<<blocks_for(n, 256), 256>>>(pinhole, grid, order == RayOrder::Tile, seed, frame, jitter, d_rays,
                                              d_pixels);
  RAYCOH_CUDA_CHECK_LAUNCH();
}

void make_primary_rays_gpu(const Camera& camera, int width, int height, RayOrder order, int tile_w, int tile_h,
                           uint32_t seed, uint32_t frame, bool jitter, PixelRays& out, float* kernel_ms) {
  if (width < 1 || height < 1 || tile_w < 1 || tile_h < 1)
    throw Error("cuda: primary rays need a positive resolution and tile size");
  const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
  DeviceBuffer<Ray> rays(n);
  DeviceBuffer<uint32_t> pixels(n);
  EventTimer timer;
  timer.start();
  launch_primary_rays(camera, width, height, order, tile_w, tile_h, seed, frame, jitter, rays.get(), pixels.get());
  timer.stop();
  const float ms = timer.elapsed_ms();
  if (kernel_ms) *kernel_ms = ms;
  out.width = width;
  out.height = height;
  out.frame = frame;
  out.rays.resize(n);
  out.pixel.resize(n);
  rays.download(out.rays.data(), n);
  pixels.download(out.pixel.data(), n);
}

void sincos_turns_gpu(const float* u, size_t n, float* s, float* c) {
  DeviceBuffer<float> du, ds(n), dc(n);
  du.upload(u, n);
  if (n > 0) {
    sincos_kernel<<<blocks_for(n, 256), 256>>>(du.get(), n, ds.get(), dc.get());
    RAYCOH_CUDA_CHECK_LAUNCH();
  }
  ds.download(s, n);
  dc.download(c, n);
}

}  // namespace raycoh::cuda
