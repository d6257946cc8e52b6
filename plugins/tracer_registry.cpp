// The explicit tracer registry: adding a tracer is one file (its doc block, parameter table and make_<name>_tracer
// factory) plus one record in tracer_infos() here. No self-registering statics: the linker would drop them from
// the static library. The CUDA tracer is registered from cuda/cuda_tracer.h in CUDA builds only.
#include "plugins/tracer_registry.h"

#include <fmt/format.h>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "scenes/scene.h"
#if defined(RAYCOH_HAVE_CUDA)
#include "cuda/cuda_tracer.h"
#endif

namespace raycoh {

// Defined in tracers/cpu_tracer.cpp, tracers/embree_tracer.cpp and simt/simt_tracer.cpp.
const ParamTable& cpu_params();
std::unique_ptr<Tracer> make_cpu_tracer(ParamSet& params, const Scene& scene, const Bvh& bvh);
const ParamTable& embree_params();
std::unique_ptr<Tracer> make_embree_tracer(ParamSet& params, const Scene& scene, const Bvh& bvh);
const ParamTable& simt_params();
std::unique_ptr<Tracer> make_simt_tracer(ParamSet& params, const Scene& scene, const Bvh& bvh);

const std::vector<TracerInfo>& tracer_infos() {
  static const std::vector<TracerInfo> infos = {
    {"cpu", "our BVH2 traversal (core/traverse.h) on the CPU, parallel over blocks of rays with oneTBB", cpu_params,
     make_cpu_tracer},
    {"embree", "Embree 3 on its own BVH: the CPU wall-clock baseline and the correctness oracle", embree_params,
     make_embree_tracer},
    {"simt", "a GPU modelled on the CPU: warps in lock step, L1/L2 cache model and a timing model (modeled ms, MRay/s)",
     simt_params, make_simt_tracer},
#if defined(RAYCOH_HAVE_CUDA)
    {"cuda",
     "our BVH2 traversal on the GPU: persistent threads (Aila & Laine 2009), kernel time from CUDA events; "
     "counters=on reproduces simt's warp counters",
     cuda_params, make_cuda_tracer},
#endif
  };
  return infos;
}

std::unique_ptr<Tracer> make_tracer(const PluginSpec& spec, const Scene& scene, const Bvh& bvh) {
#if !defined(RAYCOH_HAVE_CUDA)
  if (spec.name == "cuda")
    throw Error("tracer 'cuda': this build has no CUDA (configure with nvcc available, or -DRAYCOH_CUDA=ON)");
#endif
  const TracerInfo& info = find_plugin(tracer_infos(), "tracer", spec.name);
  ParamSet params(fmt::format("tracer '{}'", spec.name), spec.params, info.table());
  return info.make(params, scene, bvh);
}

}  // namespace raycoh
