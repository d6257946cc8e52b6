// The explicit tracer registry: adding a tracer is one file with a make_<name>_tracer function plus one entry in
// tracer_infos() and one branch in make_tracer() here. No self-registering statics: the linker would drop them
// from the static library.
//
// Parameters: each tracer reads its own from a ParamSet owned by "tracer '<name>'"; unknown keys are errors.
#include <fmt/format.h>

#include "core/error.h"
#include "bvh/bvh_build.h"
#include "tracers/tracer.h"
#include "scenes/scene.h"
#if defined(RAYCOH_HAVE_CUDA)
#include "cuda/cuda_tracer.h"
#endif

namespace raycoh {

// Defined in tracers/cpu_tracer.cpp, tracers/embree_tracer.cpp and simt/simt_tracer.cpp (cuda/cuda_tracer.h declares
// the CUDA one). The Scene and Bvh must outlive
// the tracer.
std::unique_ptr<Tracer> make_cpu_tracer(ParamSet& params, const Scene& scene, const Bvh& bvh);
std::unique_ptr<Tracer> make_embree_tracer(ParamSet& params, const Scene& scene, const Bvh& bvh);
std::unique_ptr<Tracer> make_simt_tracer(ParamSet& params, const Scene& scene, const Bvh& bvh);

void Tracer::trace_indirect(const Ray* rays, const uint32_t* order, size_t count, Hit* hits) {
  std::vector<Ray> gathered(count);
  for (size_t i = 0; i < count; ++i) gathered[i] = rays[order[i]];
  trace(gathered.data(), count, hits);
}

const std::vector<TracerInfo>& tracer_infos() {
  static const std::vector<TracerInfo> infos = {
      {"cpu", "our BVH2 traversal (core/traverse.h) on the CPU, parallel over blocks of rays with oneTBB", "(none)"},
      {"embree", "Embree 3 on its own BVH: the CPU wall-clock baseline and the correctness oracle",
       "mode=single|packet16|stream_coherent|stream_incoherent (default single), quality=high|medium (default high)"},
      {"simt", "warps of 32 consecutive rays in lock step + L1/L2 cache model: SIMT efficiency, misses, modeled cost",
       "preset=rtx3060|h100 (default rtx3060), warp=[1,64] (32), line=64|128 (64), sms=[1,1024], l1_kb=[1,65536], "
       "l2_mb=[0.002,4096] (preset's), resident=[1,64] (32), block=[1,32] (2: two warps per 8x8 tile)"},
#if defined(RAYCOH_HAVE_CUDA)
      {"cuda",
       "our BVH2 traversal on the GPU: persistent threads (Aila & Laine 2009), kernel time from CUDA events; "
       "counters=on reproduces simt's warp counters",
       "kernel=persistent|simple (persistent), block=[32,1024] multiple of 32 (128), counters=off|on (off), "
       "line=64|128 (64)"},
#endif
  };
  return infos;
}

std::unique_ptr<Tracer> make_tracer(const PluginSpec& spec, const Scene& scene, const Bvh& bvh) {
  ParamSet params(fmt::format("tracer '{}'", spec.name), spec.params);
  if (spec.name == "cpu") return make_cpu_tracer(params, scene, bvh);
  if (spec.name == "embree") return make_embree_tracer(params, scene, bvh);
  if (spec.name == "simt") return make_simt_tracer(params, scene, bvh);
  if (spec.name == "cuda") {
#if defined(RAYCOH_HAVE_CUDA)
    return make_cuda_tracer(params, scene, bvh);
#else
    throw Error("tracer 'cuda': this build has no CUDA (configure with nvcc available, or -DRAYCOH_CUDA=ON)");
#endif
  }
  std::vector<std::string> names;
  for (const TracerInfo& info : tracer_infos()) names.push_back(info.name);
  throw Error(fmt::format("unknown tracer '{}'; valid tracers: {}", spec.name, join(names)));
}

}  // namespace raycoh
