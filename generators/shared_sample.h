// The per-pixel random numbers of the prior-art generators that share them between pixels (`sadeghi`,
// `microjitter`; generators/shared_sample.cpp states the methods and their parameters), one rule for the CPU
// generator and the device kernel (cuda/device_per_pixel.cu). Plain structs and RAYCOH_HD functions only, under
// the project's floating-point rules (no FMA contraction on either side, the exact floorf and fminf), so the two
// make the same rays bit for bit.
#pragma once

#include "core/bsdf.h"
#include "core/platform.h"
#include "core/ray_batch.h"
#include "core/rng.h"

namespace raycoh {

// Pixel ids of the shared streams in rng(): far above any image's pixel numbers.
constexpr uint32_t kSharedStreamBase = 0xF0000000u;

enum class Sharing : uint8_t {
  Sadeghi,      // N x N interleaved shared streams
  MicroJitter,  // one shared stream, jittered per pixel within a radius
};

// What a pixel's numbers depend on besides seed, frame and pixel: typed, the generator's parameters.
struct SharedSampleConfig {
  Sharing sharing = Sharing::Sadeghi;
  uint32_t interleave = 1;  // sadeghi: N (>= 1)
  float radius = 0.f;       // microjitter: jitter width per dimension in [0, 1]
};

// Whether every pixel of a width x height image has its own stream (sadeghi with N^2 >= pixels): then no ray
// counts as reused.
RAYCOH_HD RAYCOH_INLINE bool shared_sample_all_own(const SharedSampleConfig& c, int width, int height) {
  return c.sharing == Sharing::Sadeghi &&
         uint64_t(c.interleave) * uint64_t(c.interleave) >= uint64_t(width) * uint64_t(height);
}

// The three numbers (direction u1, u2, lobe choice) of pixel p at (x, y). sadeghi: stream (y mod N) N + x mod N.
// microjitter: frac(shared + radius (own - 1/2)) per dimension, kept below 1 against rounding.
RAYCOH_HD RAYCOH_INLINE void shared_sample_numbers(const SharedSampleConfig& c, uint32_t seed, uint32_t frame,
                                                   uint32_t x, uint32_t y, uint32_t p, float u[3]) {
  const uint32_t dims[3] = {kDimSecondary0, kDimSecondary1, kDimSecondaryLobe};
  if (c.sharing == Sharing::Sadeghi) {
    const uint32_t n = c.interleave;
    const uint32_t stream = (y % n) * n + x % n;
    for (int d = 0; d < 3; ++d) u[d] = rng_float(seed, frame, kSharedStreamBase + stream, dims[d]);
    return;
  }
  for (int d = 0; d < 3; ++d) {
    const float shared = rng_float(seed, frame, kSharedStreamBase, dims[d]);
    const float jitter = rng_float(seed, frame, p, dims[d]);
    const float v = shared + c.radius * (jitter - 0.5f);
    u[d] = fminf(v - floorf(v), 0x1.fffffep-1f);
  }
}

// Pixel p's direction at sp (material m) with its shared numbers: its own BSDF sampled (core/bsdf.h).
RAYCOH_HD RAYCOH_INLINE DirectionSample shared_sample_direction(const SharedSampleConfig& c, const BsdfParams& m,
                                                                const ShadingPoint& sp, uint32_t seed, uint32_t frame,
                                                                uint32_t x, uint32_t y, uint32_t p) {
  float u[3];
  shared_sample_numbers(c, seed, frame, x, y, p, u);
  return sample_direction(m, sp.ns, sp.ng, sp.wo, sp.front_face, u[0], u[1], u[2]);
}

}  // namespace raycoh
