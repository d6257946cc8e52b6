// raycoh_bench_simt: the `simt` tracer (simt/simt.h, simt/cache_model.h, simt/timed_replay.h) on real secondary-ray
// batches, with its coherence counters as benchmark counters, registered at run time per scene, generator and tracer.
//
//   simt/<scene>/<generator>/<tracer>   one Tracer::trace call over the batch (wall-clock of the model, not a
//                                       GPU time); the counters are the point:
//     eff        SIMT efficiency, node and leaf steps pooled; node_eff, leaf_eff each kind alone
//     nodes/ray  per-ray node visits (speculative walks included)
//     nlines/ray node transactions (distinct lines per node step) per ray; tlines/ray the same for triangles
//     fetch/ray  sectors requested from L1 per ray; l1miss/ray, l2miss/ray in sectors; dram_B/ray bytes
//     modeled_mray_s  the timing model's MRay/s on the preset GPU (modeled, simt/timed_replay.h)
//   Batches: frame 0 of the G-buffer from jittered camera rays (seed 1), secondary rays from the generator, in
//   its batch order. Generators: noopt (tile order, the default) and noopt:order=scanline.
//   Tracers: simt (preset rtx3060) and simt:preset=h100.
//
// Scenes: the built-in cornell and voxels, then every .glb under $RAYCOH_SCENES or, without it, the shared scenes
// directory fixed at configure time. Select with --benchmark_filter (a regex on the names above). One scene and
// its batches are held at a time.
//
// Environment: RAYCOH_BENCH_SIZE=WxH (default 480x270, each in [1, 8192]) sets the image size;
// RAYCOH_BENCH_GENERATORS and RAYCOH_BENCH_TRACERS (comma-separated plugin lists, e.g. "noopt,ours:k=16")
// replace the default generators and tracers. Each case runs once (the counters are deterministic); use
// --benchmark_repetitions for timing statistics.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "bench/bench_common.h"
#include "bvh/bvh_build.h"
#include "core/error.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "generators/primary.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

std::pair<int, int> size() { return bench::image_size({480, 270}); }

std::vector<std::string> plugin_list(const char* env, std::vector<std::string> defaults) {
  const char* text = std::getenv(env);
  if (!text) return defaults;
  std::vector<std::string> out;
  for (const PluginSpec& spec : split_plugin_list(text)) out.push_back(spec.text());
  return out;
}

void bm_simt(benchmark::State& state, const std::string& scene_spec, const std::string& generator,
             const std::string& tracer_spec) {
  try {
    bench::Frame& f = bench::frame(scene_spec, size());
    const std::vector<Ray>& rays = f.batch(generator).rays;
    auto tracer = make_tracer(parse_plugin_spec(tracer_spec), f.scene, f.bvh);
    std::vector<Hit> hits(rays.size());
    for (auto _ : state) {
      tracer->trace(rays.data(), rays.size(), hits.data());
      benchmark::ClobberMemory();
    }
    const CoherenceCounters& c = *tracer->last_counters();
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(rays.size()));
    state.counters["rays"] = static_cast<double>(c.rays);
    state.counters["eff"] = c.simt_efficiency();
    state.counters["node_eff"] = c.node_simt_efficiency();
    state.counters["leaf_eff"] = c.leaf_simt_efficiency();
    state.counters["nodes/ray"] = c.per_ray(c.nodes);
    state.counters["nlines/ray"] = c.per_ray(c.node_lines);
    state.counters["tlines/ray"] = c.per_ray(c.triangle_lines);
    state.counters["fetch/ray"] = c.fetches_per_ray();
    state.counters["l1miss/ray"] = c.l1_misses_per_ray();
    state.counters["l2miss/ray"] = c.l2_misses_per_ray();
    state.counters["dram_B/ray"] = c.dram_bytes_per_ray();
    state.counters["modeled_mray_s"] = c.modeled_mray_s();
  } catch (const Error& e) {
    state.SkipWithError(e.what());
  }
}

void register_benchmarks() {
  const auto generators = plugin_list("RAYCOH_BENCH_GENERATORS", {"noopt", "noopt:order=scanline"});
  const auto tracers = plugin_list("RAYCOH_BENCH_TRACERS", {"simt", "simt:preset=h100"});
  for (const auto& [name, spec] : bench::scenes())
    for (const std::string& generator : generators)
      for (const std::string& tracer : tracers)
        benchmark::RegisterBenchmark(("simt/" + name + "/" + generator + "/" + tracer).c_str(), bm_simt, spec,
                                     generator, tracer)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime()
            ->Iterations(1);
}

}  // namespace
}  // namespace raycoh

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  try {
    const auto [width, height] = raycoh::size();
    benchmark::AddCustomContext("image", std::to_string(width) + "x" + std::to_string(height));
    raycoh::register_benchmarks();
  } catch (const raycoh::Error& e) {
    std::fprintf(stderr, "raycoh_bench_simt: error: %s\n", e.what());
    return 2;
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
