// The `cuda` tracer's parameter table and factory, for the tracer registry (plugins/tracer_registry.cpp); CUDA builds
// only.
#pragma once

#include <memory>

#include "core/params.h"
#include "tracers/tracer.h"

namespace raycoh {

struct Scene;
struct Bvh;

// Defined in cuda/cuda_tracer.cpp. Throws raycoh::Error when there is no CUDA device. The Scene and Bvh must
// outlive the tracer.
const ParamTable& cuda_params();
std::unique_ptr<Tracer> make_cuda_tracer(ParamSet& params, const Scene& scene, const Bvh& bvh);

}  // namespace raycoh
