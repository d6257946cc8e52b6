// The explicit tracer registry: adding a tracer is one file (its doc block, parameter table and make_<name>_tracer
// factory) plus one record in tracer_infos() here. No self-registering statics: the linker would drop them from
// the static library. The CUDA tracer is registered from cuda/cuda_tracer.h in CUDA builds only.
#include <fmt/format.h>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "scenes/scene.h"
#include "simt/cache_model.h"
#include "tracers/tracer.h"
#if defined(RAYCOH_HAVE_CUDA)
#include "cuda/cuda_tracer.h"
#endif

namespace raycoh {

// Defined in tracers/cpu_tracer.cpp, tracers/embree_tracer.cpp and simt/simt_tracer.cpp.
const ParamTable& cpu_params();
std::unique_ptr<Tracer> make_cpu_tracer(ParamSet& params, const Scene& scene, const Bvh& bvh);
const ParamTable& embree_params();
std::unique_ptr<Tracer> make_embree_tracer(ParamSet& params, const Scene& scene, const Bvh& bvh);
std::unique_ptr<Tracer> make_simt_tracer(ParamSet& params, const Scene& scene, const Bvh& bvh);

namespace {

// Transitional, for `raycoh list` only: simt/simt_tracer.cpp still reads its parameters with explicit defaults
// (most of them the cache preset's), and moves this table next to its factory when it reads through one.
const ParamTable& simt_params() {
  auto preset_int = [](const char* name, int lo, int hi, const char* doc) {
    return ParamSpec{name, ParamType::Int, "preset", double(lo), double(hi), {}, doc};
  };
  static const ParamTable table = {
      choice_param("preset", "rtx3060", cache_preset_names(), "GPU whose caches and SMs are modelled"),
      int_param("warp", 32, 1, 64, "lanes per warp"),
      choice_param("line", "64", {"64", "128"}, "bytes per counted line"),
      preset_int("sms", 1, 1024, "streaming multiprocessors"),
      preset_int("l1_kb", 1, 65536, "L1 capacity per SM in KiB"),
      ParamSpec{"l2_mb", ParamType::Float, "preset", 0.002, 4096, {}, "L2 capacity in MiB"},
      preset_int("resident", 1, 64, "warps resident per SM"),
      preset_int("block", 1, 32, "warps per block (2: two warps per 8x8 tile)"),
  };
  return table;
}

}  // namespace

void Tracer::trace_indirect(const Ray* rays, const uint32_t* order, size_t count, Hit* hits) {
  std::vector<Ray> gathered(count);
  for (size_t i = 0; i < count; ++i) gathered[i] = rays[order[i]];
  trace(gathered.data(), count, hits);
}

const std::vector<TracerInfo>& tracer_infos() {
  static const std::vector<TracerInfo> infos = {
    {"cpu", "our BVH2 traversal (core/traverse.h) on the CPU, parallel over blocks of rays with oneTBB", cpu_params,
     make_cpu_tracer},
    {"embree", "Embree 3 on its own BVH: the CPU wall-clock baseline and the correctness oracle", embree_params,
     make_embree_tracer},
    {"simt", "warps of 32 consecutive rays in lock step + L1/L2 cache model: SIMT efficiency, misses, modeled cost",
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
