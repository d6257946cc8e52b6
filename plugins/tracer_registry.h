// The tracer registry: every tracer by name, the CPU ones of tracers/, `simt` (simt/) and, in CUDA builds, `cuda`
// (cuda/). It sits above all three, so no tracer folder includes another's.
#pragma once

#include <memory>
#include <vector>

#include "core/params.h"
#include "tracers/tracer.h"

namespace raycoh {

struct Scene;
struct Bvh;

// The explicit registry (adding a tracer = one file + one record in plugins/tracer_registry.cpp).
const std::vector<TracerInfo>& tracer_infos();
// Throws raycoh::Error for unknown names or bad parameters, naming the valid choices.
std::unique_ptr<Tracer> make_tracer(const PluginSpec& spec, const Scene& scene, const Bvh& bvh);

}  // namespace raycoh
