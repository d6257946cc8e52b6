// A first hit's own BSDF sample with NoOpt's random numbers: the one call every generator (CPU and CUDA) makes
// when a pixel samples for itself.
#pragma once

#include "core/bsdf.h"
#include "core/platform.h"
#include "core/ray_batch.h"
#include "core/rng.h"

namespace raycoh {

RAYCOH_HD RAYCOH_INLINE DirectionSample sample_own_lobe(const BsdfParams& m, const ShadingPoint& sp, uint32_t seed,
                                                        uint32_t frame, uint32_t pixel) {
  return sample_direction(m, sp.ns, sp.ng, sp.wo, sp.front_face, rng_float(seed, frame, pixel, kDimSecondary0),
                          rng_float(seed, frame, pixel, kDimSecondary1),
                          rng_float(seed, frame, pixel, kDimSecondaryLobe));
}

}  // namespace raycoh
