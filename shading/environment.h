// The environment light of scenes without emitters (docs/design.md section 6): a sky gradient and a sun disc.
// Radiance lookups for rays that miss the scene (sky_radiance, in_sun_cone, environment_radiance), the sun's cone
// pdf and its sampler for next-event estimation (sun_on, sun_cone_pdf, SunSampler) are host/device functions in
// core/environment_light.h, so that the CPU path tracer and the device one (cuda/device_shading.cu) compute the
// same light from the same code.
#pragma once

#include "core/environment_light.h"
#include "core/sampling.h"
#include "scenes/scene.h"
