// Stateless random numbers: every number is a hash of (seed, frame, pixel, dimension), so a batch is the same
// whatever the thread count, the ray order or the device that makes it.
#pragma once

#include "core/platform.h"

namespace raycoh {

// "lowbias32" integer hash (C. Wellons, hash-prospector): full avalanche, cheap on CPU and GPU.
RAYCOH_HD RAYCOH_INLINE uint32_t hash32(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

RAYCOH_HD RAYCOH_INLINE uint32_t rng_u32(uint32_t seed, uint32_t frame, uint32_t pixel, uint32_t dim) {
  return hash32(seed ^ hash32(frame ^ hash32(pixel ^ hash32(dim + 0x9e3779b9u))));
}

// Uniform float in [0, 1) with 24 random bits (exactly representable, never 1).
RAYCOH_HD RAYCOH_INLINE float rng_float(uint32_t seed, uint32_t frame, uint32_t pixel, uint32_t dim) {
  return static_cast<float>(rng_u32(seed, frame, pixel, dim) >> 8) * (1.f / 16777216.f);
}

// Dimensions used by the pipeline, so that stages never reuse each other's numbers.
enum RngDim : uint32_t {
  kDimPixelJitterX = 0,
  kDimPixelJitterY = 1,
  kDimSecondary0 = 2,  // first bounce direction
  kDimSecondary1 = 3,
  kDimSecondaryLobe = 4,  // discrete lobe choice (reflect / refract)
  kDimTileShuffleA = 5,   // per tile (the "pixel" argument is the tile index): shuffle multiplier
  kDimTileShuffleC = 6,   // per tile: shuffle increment
  kDimGroupDonor = 7,     // per group (the "pixel" argument is the frame-unique group id): donor member
  kDimGroupGlossy = 8,    // per group: the glossy member whose direction `ours:hybrid=glossy` reuses
  kDimFirstFree = 16,     // later stages start here
};

}  // namespace raycoh
