// Generation overhead of the secondary-ray generators against NoOpt and against the secondary-ray trace time
// (issue goal: ours costs at most 1% of the trace time more than NoOpt), at 1920x1080 by default.
//
//   build/bench/raycoh_bench_generate [--benchmark_min_time=0.5]
//   RAYCOH_BENCH_SIZE=WxH   image size (default 1920x1080)
//   RAYCOH_SCENES=DIR       folder of the shared scenes (default: shared/scenes beside the repository); sibenik
//                           and country_kitchen are used when present, the built-in voxels scene always
//
// Benchmarks: generate/<scene>/<generator> (one frame's batch from a fixed G-buffer) and
// trace/<scene>/<generator>/cpu (that batch traced by the `cpu` tracer). After the run a summary prints, per
// scene, (t_gen(ours) - t_gen(noopt)) / t_trace(ours batch) from the means measured in this same run.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>

#include "bench/bench_common.h"
#include "bvh/bvh_build.h"
#include "core/params.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "generators/primary.h"
#include "plugins/tracer_registry.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

std::pair<int, int> bench_size() { return bench::image_size({1920, 1080}); }

std::map<std::string, double>& mean_seconds() {  // "kind/scene/generator" -> mean seconds per iteration
  static std::map<std::string, double> m;
  return m;
}

void bm_generate(benchmark::State& state, const std::string& name, const std::string& spec, const std::string& gen) {
  bench::Frame& f = bench::frame(spec, bench_size());
  auto generator = make_generator(parse_plugin_spec(gen));
  RayBatch batch;
  GenerationStats stats;
  double total = 0;
  int64_t n = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    generator->generate(f.scene, f.gbuffer, bench::kSeed, batch, stats);
    total += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++n;
  }
  state.SetItemsProcessed(n * static_cast<int64_t>(batch.size()));
  mean_seconds()["generate/" + name + "/" + gen] = total / static_cast<double>(n);
}

void bm_trace(benchmark::State& state, const std::string& name, const std::string& spec, const std::string& gen) {
  bench::Frame& f = bench::frame(spec, bench_size());
  const RayBatch& batch = f.batch(gen);
  const auto tracer = make_tracer({"cpu", ""}, f.scene, f.bvh);
  std::vector<Hit> hits(batch.size());
  double total = 0;
  int64_t n = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    tracer->trace(batch.rays.data(), batch.size(), hits.data());
    total += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++n;
  }
  state.SetItemsProcessed(n * static_cast<int64_t>(batch.size()));
  state.counters["MRay/s"] = benchmark::Counter(static_cast<double>(n * batch.size()) * 1e-6 / total);
  mean_seconds()["trace/" + name + "/" + gen] = total / static_cast<double>(n);
}

}  // namespace
}  // namespace raycoh

int main(int argc, char** argv) {
  using namespace raycoh;
  const std::vector<std::string> generators = {"noopt", "ours", "tile", "direct"};
  std::vector<std::pair<std::string, std::string>> scenes;
  for (const auto& [name, spec] : bench::scenes({"sibenik", "country_kitchen"}))
    scenes.emplace_back(name, name == "voxels" ? "voxels:size=128" : spec);
  for (const auto& [name, spec] : scenes) {
    for (const std::string& g : generators)
      benchmark::RegisterBenchmark(("generate/" + name + "/" + g).c_str(), bm_generate, name, spec, g)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    for (const std::string& g : {std::string("noopt"), std::string("ours")})
      benchmark::RegisterBenchmark(("trace/" + name + "/" + g + "/cpu").c_str(), bm_trace, name, spec, g)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();

  const auto& m = mean_seconds();
  const auto [w, h] = bench_size();
  std::printf("\nGeneration overhead of ours over noopt, as a share of tracing the ours batch (%dx%d, cpu tracer):\n",
              w, h);
  for (const auto& [name, spec] : scenes) {
    const auto g_ours = m.find("generate/" + name + "/ours"), g_noopt = m.find("generate/" + name + "/noopt");
    const auto t_ours = m.find("trace/" + name + "/ours");
    if (g_ours == m.end() || g_noopt == m.end() || t_ours == m.end()) continue;
    std::printf("  %-16s gen noopt %.2f ms, gen ours %.2f ms, trace %.1f ms: overhead %+.2f%% of trace\n", name.c_str(),
                g_noopt->second * 1e3, g_ours->second * 1e3, t_ours->second * 1e3,
                100.0 * (g_ours->second - g_noopt->second) / t_ours->second);
  }
  return 0;
}
