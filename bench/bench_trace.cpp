// raycoh_bench: Google Benchmark timings of the CPU side of the pipeline, registered at run time per scene.
//
//   build/<scene>                          build_bvh (Embree binned SAH + flattening), default BvhBuildConfig
//   trace/<scene>/<rays>/<tracer>          one Tracer::trace call over the whole batch; counter MRay/s
//     rays   primary    camera rays of one frame, 8x8 tile order (the harness default; bench/bench_common.h)
//            secondary  the noopt batch made from that frame's G-buffer, same order
//     tracer cpu | embree:mode=single | embree:mode=packet16 | embree:mode=stream_coherent |
//            embree:mode=stream_incoherent | embree:mode=single,quality=medium
//
// Scenes: the built-in cornell and voxels, then every .glb under $RAYCOH_SCENES or, without it, the shared scenes
// directory fixed at configure time. Select with --benchmark_filter (a regex on the names above). Each scene is
// loaded, its BVH built and its rays made once, when its first benchmark runs; only one scene (and one tracer)
// is held at a time, so the large scenes do not pile up in memory.
//
// Environment: RAYCOH_BENCH_SIZE=WxH (default 1024x768) sets the image size; RAYCOH_SCENES the scenes folder.
// Times are wall-clock (UseRealTime): the tracers run on every core through oneTBB.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "bench/bench_common.h"
#include "bvh/bvh_build.h"
#include "core/error.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "embree/embree_device.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

std::pair<int, int> size() { return bench::image_size({1024, 768}); }

// The one tracer held at a time; it refers to the held frame's scene and BVH, so it goes first.
struct TracerCache {
  std::string key;
  std::unique_ptr<Tracer> tracer;
};
TracerCache held_tracer;

Tracer& tracer_for(const std::string& scene_spec, const std::string& tracer_spec) {
  bench::Frame& f = bench::frame(scene_spec, size());
  const std::string key = scene_spec + "|" + tracer_spec;
  if (!held_tracer.tracer || held_tracer.key != key) {
    held_tracer.tracer.reset();
    held_tracer.tracer = make_tracer(parse_plugin_spec(tracer_spec), f.scene, f.bvh);
    held_tracer.key = key;
  }
  return *held_tracer.tracer;
}

void bm_build(benchmark::State& state, const std::string& spec) {
  try {
    const Scene& scene = bench::frame(spec, size()).scene;
    BvhStats stats;
    for (auto _ : state) {
      Bvh bvh = build_bvh(scene);
      stats = bvh.stats;
      benchmark::DoNotOptimize(bvh.nodes.data());
    }
    const double tris = static_cast<double>(scene.triangle_count());
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(scene.triangle_count()));
    state.counters["MTri/s"] = benchmark::Counter(tris * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
    state.counters["tris"] = tris;
    state.counters["nodes"] = static_cast<double>(stats.inner_nodes);
    state.counters["depth"] = static_cast<double>(stats.max_depth);
    state.counters["SAH"] = stats.sah_cost;
  } catch (const Error& e) {
    state.SkipWithError(e.what());
  }
}

void bm_trace(benchmark::State& state, const std::string& scene_spec, bool secondary, const std::string& tracer_spec) {
  try {
    Tracer& tracer = tracer_for(scene_spec, tracer_spec);
    bench::Frame& f = bench::frame(scene_spec, size());
    const std::vector<Ray>& rays = secondary ? f.batch("noopt").rays : f.primary.rays;
    std::vector<Hit> hits(rays.size());
    for (auto _ : state) {
      tracer.trace(rays.data(), rays.size(), hits.data());
      benchmark::ClobberMemory();
    }
    const auto hit_count = std::count_if(hits.begin(), hits.end(), [](const Hit& h) { return h.valid(); });
    const double n = static_cast<double>(rays.size());
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(rays.size()));
    state.counters["MRay/s"] = benchmark::Counter(n * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
    state.counters["rays"] = n;
    state.counters["hit%"] = n > 0 ? 100.0 * static_cast<double>(hit_count) / n : 0.0;
  } catch (const Error& e) {
    state.SkipWithError(e.what());
  }
}

void register_benchmarks() {
  // The last one traces Embree's single-ray kernel on a tree built like ours (binned SAH), to separate tree
  // quality from traversal speed.
  const std::vector<std::string> tracers = {"cpu",
                                            "embree:mode=single",
                                            "embree:mode=packet16",
                                            "embree:mode=stream_coherent",
                                            "embree:mode=stream_incoherent",
                                            "embree:mode=single,quality=medium"};
  for (const auto& [name, spec] : bench::scenes()) {
    benchmark::RegisterBenchmark(("build/" + name).c_str(), bm_build, spec)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
    for (const std::string& tracer : tracers)
      for (const bool secondary : {false, true})
        benchmark::RegisterBenchmark(
            ("trace/" + name + "/" + (secondary ? "secondary" : "primary") + "/" + tracer).c_str(), bm_trace, spec,
            secondary, tracer)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
  }
}

}  // namespace
}  // namespace raycoh

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  try {
    const auto [width, height] = raycoh::size();
    benchmark::AddCustomContext("embree", raycoh::embree_version());
    benchmark::AddCustomContext("image", std::to_string(width) + "x" + std::to_string(height) + ", 8x8 tile order");
    raycoh::register_benchmarks();
  } catch (const raycoh::Error& e) {
    std::fprintf(stderr, "raycoh_bench: error: %s\n", e.what());
    return 2;
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  // Release the held tracer before static destruction, while Embree's device is still alive.
  raycoh::held_tracer.tracer.reset();
  return 0;
}
