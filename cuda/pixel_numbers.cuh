// How a pixel of the per-pixel generators (noopt, sadeghi, microjitter) samples its direction, and the launches of
// their kernel (cuda/device_per_pixel.cu) and its fused form (cuda/fused_kernels.cu). Shared by those kernels and
// the host side that picks them (cuda/device_generators.cu). Included by .cu files only.
#pragma once

#include <cstdint>

#include "core/own_lobe.h"
#include "cuda/device_common.cuh"
#include "generators/shared_sample.h"

namespace raycoh::cuda {

// How a pixel of the per-pixel kernel samples: its own numbers (noopt), or shared ones (sadeghi, microjitter:
// generators/shared_sample.h, the rule the CPU generator calls). `reused` says whether the ray counts as reused.
struct OwnNumbers {
  static constexpr bool kCountsReuse = false;
  __device__ DirectionSample operator()(const BsdfParams& m, const ShadingPoint& sp, uint32_t seed, uint32_t frame,
                                        uint32_t, uint32_t, uint32_t p) const {
    return sample_own_lobe(m, sp, seed, frame, p);
  }
};
struct SharedNumbers {
  static constexpr bool kCountsReuse = true;
  SharedSampleConfig config;
  bool reused;  // !shared_sample_all_own for this image
  __device__ DirectionSample operator()(const BsdfParams& m, const ShadingPoint& sp, uint32_t seed, uint32_t frame,
                                        uint32_t x, uint32_t y, uint32_t p) const {
    return shared_sample_direction(config, m, sp, seed, frame, x, y, p);
  }
};

// The per-pixel kernel (noopt; sadeghi, microjitter with `shared`): one block per tile of grid, each hit pixel's
// ray written at offsets[tile] + its rank among the tile's hits in row-major order, statistics into stats
// (kStatCount slots). Queued on the default stream.
void launch_per_pixel_kernel(const TileGrid& grid, const ShadingPoint* points, const BsdfParams* materials,
                             uint32_t seed, uint32_t frame, const uint32_t* offsets, const BatchView& out,
                             unsigned long long* stats, const SharedNumbers* shared);

// Its fused form (cuda/fused_kernels.cu): the same rays made and traced by one block per tile with the launch's
// kernel form over `scene`; hits and batch as launch_fused_grouping's (cuda/device_common.cuh).
void launch_fused_per_pixel(const DeviceScene& scene, const TraceLaunch& launch, const ShadingPoint* points,
                            const BsdfParams* materials, uint32_t seed, uint32_t frame, const TileGrid& grid,
                            const FusedBatch& batch, Hit* hits, unsigned long long* stats, const SharedNumbers* shared);

}  // namespace raycoh::cuda
