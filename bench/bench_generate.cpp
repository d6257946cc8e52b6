// Generation overhead of the secondary-ray generators against NoOpt and against the secondary-ray trace time
// (issue goal: ours costs at most 1% of the trace time more than NoOpt), at 1920x1080 by default.
//
//   build/bench/raycoh_bench_generate [--benchmark_min_time=0.5]
//   RAYCOH_BENCH_SIZE=WxH   image size (default 1920x1080)
//   RAYCOH_SCENES=DIR       folder of the shared scenes (default ../shared/scenes); sibenik and country_kitchen
//                           are used when present, the built-in voxels scene always
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

#include "core/params.h"
#include "cpu/bvh_build.h"
#include "cpu/tracer.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "generators/primary.h"

namespace raycoh {
namespace {

struct Frame {
  Scene scene;
  Bvh bvh;
  GBuffer gbuffer;
  std::unique_ptr<Tracer> tracer;
};

std::pair<int, int> bench_size() {
  if (const char* env = std::getenv("RAYCOH_BENCH_SIZE")) return parse_size("RAYCOH_BENCH_SIZE", env, 1, 16384);
  return {1920, 1080};
}

Frame& frame_for(const std::string& spec) {
  static std::map<std::string, std::unique_ptr<Frame>> cache;
  auto& slot = cache[spec];
  if (!slot) {
    cache.clear();  // one scene in memory at a time
    auto f = std::make_unique<Frame>();
    f->scene = load_scene(spec);
    f->bvh = build_bvh(f->scene);
    f->tracer = make_tracer({"cpu", ""}, f->scene, f->bvh);
    const auto [w, h] = bench_size();
    const PrimaryBatch primary =
        make_primary_rays(f->scene.camera, w, h, make_pixel_order(w, h, RayOrder::Tile, 8, 8), 1, 0, true);
    std::vector<Hit> hits(primary.rays.size());
    f->tracer->trace(primary.rays.data(), primary.rays.size(), hits.data());
    f->gbuffer = make_gbuffer(f->scene, primary, hits);
    cache[spec] = std::move(f);
  }
  return *cache[spec];
}

std::map<std::string, double>& mean_seconds() {  // "kind/scene/generator" -> mean seconds per iteration
  static std::map<std::string, double> m;
  return m;
}

void bm_generate(benchmark::State& state, const std::string& name, const std::string& spec, const std::string& gen) {
  Frame& f = frame_for(spec);
  auto generator = make_generator(parse_plugin_spec(gen));
  RayBatch batch;
  GenerationStats stats;
  double total = 0;
  int64_t n = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    generator->generate(f.scene, f.gbuffer, 1, batch, stats);
    total += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++n;
  }
  state.SetItemsProcessed(n * static_cast<int64_t>(batch.size()));
  mean_seconds()["generate/" + name + "/" + gen] = total / static_cast<double>(n);
}

void bm_trace(benchmark::State& state, const std::string& name, const std::string& spec, const std::string& gen) {
  Frame& f = frame_for(spec);
  RayBatch batch;
  GenerationStats stats;
  make_generator(parse_plugin_spec(gen))->generate(f.scene, f.gbuffer, 1, batch, stats);
  std::vector<Hit> hits(batch.size());
  double total = 0;
  int64_t n = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    f.tracer->trace(batch.rays.data(), batch.size(), hits.data());
    total += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++n;
  }
  state.SetItemsProcessed(n * static_cast<int64_t>(batch.size()));
  state.counters["MRay/s"] = benchmark::Counter(static_cast<double>(n * batch.size()) * 1e-6 / total);
  mean_seconds()["trace/" + name + "/" + gen] = total / static_cast<double>(n);
}

std::vector<std::pair<std::string, std::string>> bench_scenes() {
  std::vector<std::pair<std::string, std::string>> scenes = {{"voxels", "voxels:size=128"}};
  std::filesystem::path dir = RAYCOH_SHARED_SCENES;
  if (const char* env = std::getenv("RAYCOH_SCENES")) dir = env;
  for (const char* name : {"sibenik", "country_kitchen"}) {
    const auto path = dir / name / (std::string(name) + ".glb");
    if (std::filesystem::exists(path)) scenes.emplace_back(name, path.string());
  }
  return scenes;
}

}  // namespace
}  // namespace raycoh

int main(int argc, char** argv) {
  using namespace raycoh;
  const std::vector<std::string> generators = {"noopt", "ours", "tile", "direct"};
  const auto scenes = bench_scenes();
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
  std::printf("\nGeneration overhead of ours over noopt, as a share of tracing the ours batch (%dx%d, cpu tracer):\n", w, h);
  for (const auto& [name, spec] : scenes) {
    const auto g_ours = m.find("generate/" + name + "/ours"), g_noopt = m.find("generate/" + name + "/noopt");
    const auto t_ours = m.find("trace/" + name + "/ours");
    if (g_ours == m.end() || g_noopt == m.end() || t_ours == m.end()) continue;
    std::printf("  %-16s gen noopt %.2f ms, gen ours %.2f ms, trace %.1f ms: overhead %+.2f%% of trace\n",
                name.c_str(), g_noopt->second * 1e3, g_ours->second * 1e3, t_ours->second * 1e3,
                100.0 * (g_ours->second - g_noopt->second) / t_ours->second);
  }
  return 0;
}
