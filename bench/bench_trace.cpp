// raycoh_bench: Google Benchmark timings of the CPU side of the pipeline, registered at run time per scene.
//
//   build/<scene>                          build_bvh (Embree binned SAH + flattening), default BvhBuildConfig
//   trace/<scene>/<rays>/<tracer>          one Tracer::trace call over the whole batch; counter MRay/s
//     rays   primary  pinhole camera rays through the pixel centres, 8x8 tile order (the harness default)
//            diffuse  one cosine-distributed ray per primary hit (offset origin, geometric normal), same order
//     tracer cpu | embree:mode=single | embree:mode=packet16 | embree:mode=stream_coherent |
//            embree:mode=stream_incoherent | embree:mode=single,quality=medium
//
// Scenes: the built-in cornell and voxels, then every .glb under $RAYCOH_SCENES or, without it, the shared scenes
// directory fixed at configure time. Select with --benchmark_filter (a regex on the names above). Each scene is
// loaded, its BVH built and its rays made once, when its first benchmark runs; only one scene (and one tracer)
// is held at a time, so the large scenes do not pile up in memory.
//
// Environment: RAYCOH_BENCH_SIZE=WxH (default 1024x768, each in [1, 8192]) sets the image size.
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

#include "core/error.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "cpu/bvh_build.h"
#include "cpu/embree_device.h"
#include "cpu/tracer.h"
#include "scenes/scene.h"

namespace raycoh {
namespace {

constexpr int kTile = 8;
constexpr uint32_t kSeed = 0x5eed;

struct Size {
  int width = 1024, height = 768;
};

Size bench_size() {
  Size size;
  if (const char* env = std::getenv("RAYCOH_BENCH_SIZE"))
    std::tie(size.width, size.height) = parse_size("RAYCOH_BENCH_SIZE", env, 1, 8192);
  return size;
}

// Pinhole camera rays through pixel centres, 8x8 tiles in row-major order, row-major inside a tile.
std::vector<Ray> primary_rays(const Camera& cam, int width, int height) {
  const Vec3 forward = normalize(cam.target - cam.eye);
  const Vec3 right = normalize(cross(forward, cam.up));
  const Vec3 up = cross(right, forward);
  const float tan_half = std::tan(cam.vfov_deg * 0.5f * kPi / 180.f);
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  std::vector<Ray> rays;
  rays.reserve(size_t(width) * height);
  for (int ty = 0; ty < height; ty += kTile)
    for (int tx = 0; tx < width; tx += kTile)
      for (int y = ty; y < std::min(ty + kTile, height); ++y)
        for (int x = tx; x < std::min(tx + kTile, width); ++x) {
          const float sx = (2.f * (x + 0.5f) / width - 1.f) * tan_half * aspect;
          const float sy = (1.f - 2.f * (y + 0.5f) / height) * tan_half;
          rays.push_back(Ray{cam.eye, 0.f, normalize(forward + right * sx + up * sy), __builtin_huge_valf()});
        }
  return rays;
}

// One cosine-distributed ray per primary hit, around the geometric normal facing the camera ray.
std::vector<Ray> diffuse_rays(const Scene& scene, const std::vector<Ray>& primary, const std::vector<Hit>& hits) {
  std::vector<Ray> rays;
  rays.reserve(primary.size());
  for (size_t i = 0; i < primary.size(); ++i) {
    const Hit& h = hits[i];
    if (!h.valid()) continue;
    const Vec3 v0 = scene.positions[scene.indices[3 * size_t{h.prim}]];
    const Vec3 v1 = scene.positions[scene.indices[3 * size_t{h.prim} + 1]];
    const Vec3 v2 = scene.positions[scene.indices[3 * size_t{h.prim} + 2]];
    Vec3 ng = normalize(cross(v1 - v0, v2 - v0));
    if (dot(ng, primary[i].dir) > 0.f) ng = -ng;
    const Vec3 p = v0 * (1.f - h.u - h.v) + v1 * h.u + v2 * h.v;
    const auto key = static_cast<uint32_t>(i);
    const Vec3 local =
        sample_cosine_hemisphere(rng_float(kSeed, 0, key, kDimSecondary0), rng_float(kSeed, 0, key, kDimSecondary1));
    rays.push_back(
        Ray{offset_ray_origin(p, ng), 0.f, normalize(make_frame(ng).to_world(local)), __builtin_huge_valf()});
  }
  return rays;
}

struct LoadedScene {
  Scene scene;
  Bvh bvh;
  std::vector<Ray> primary, diffuse;
};

// The one scene and the one tracer held at a time. Benchmarks are registered scene by scene and tracer by
// tracer, so each is made once. The tracer goes first: it refers to the scene and its BVH.
struct Cache {
  std::string scene_spec;
  std::unique_ptr<LoadedScene> scene;
  std::string tracer_spec;
  std::unique_ptr<Tracer> tracer;
};
Cache cache;

void release_cache() {
  cache.tracer.reset();
  cache.tracer_spec.clear();
  cache.scene.reset();
  cache.scene_spec.clear();
}

LoadedScene& loaded(const std::string& spec) {
  if (cache.scene && cache.scene_spec == spec) return *cache.scene;
  release_cache();
  auto s = std::make_unique<LoadedScene>();
  s->scene = load_scene(spec);
  s->bvh = build_bvh(s->scene);
  const Size size = bench_size();
  s->primary = primary_rays(s->scene.camera, size.width, size.height);
  auto cpu = make_tracer(parse_plugin_spec("cpu"), s->scene, s->bvh);
  std::vector<Hit> hits(s->primary.size());
  cpu->trace(s->primary.data(), s->primary.size(), hits.data());
  s->diffuse = diffuse_rays(s->scene, s->primary, hits);
  cache.scene = std::move(s);
  cache.scene_spec = spec;
  return *cache.scene;
}

Tracer& tracer_for(const std::string& scene_spec, const std::string& tracer_spec) {
  LoadedScene& s = loaded(scene_spec);
  const std::string key = scene_spec + "|" + tracer_spec;
  if (!cache.tracer || cache.tracer_spec != key) {
    cache.tracer.reset();
    cache.tracer = make_tracer(parse_plugin_spec(tracer_spec), s.scene, s.bvh);
    cache.tracer_spec = key;
  }
  return *cache.tracer;
}

void bm_build(benchmark::State& state, const std::string& spec) {
  try {
    const Scene& scene = loaded(spec).scene;
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

void bm_trace(benchmark::State& state, const std::string& scene_spec, bool diffuse, const std::string& tracer_spec) {
  try {
    Tracer& tracer = tracer_for(scene_spec, tracer_spec);
    const std::vector<Ray>& rays = diffuse ? cache.scene->diffuse : cache.scene->primary;
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

std::vector<std::pair<std::string, std::string>> bench_scenes() {  // (name, spec)
  std::vector<std::pair<std::string, std::string>> scenes = {{"cornell", "cornell"}, {"voxels", "voxels"}};
  std::filesystem::path dir;
  if (const char* env = std::getenv("RAYCOH_SCENES"))
    dir = env;
  else
    dir = RAYCOH_SHARED_SCENES;
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  if (std::filesystem::is_directory(dir, ec))
    for (const auto& entry : std::filesystem::recursive_directory_iterator(dir, ec))
      if (entry.path().extension() == ".glb") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  for (const auto& f : files) scenes.emplace_back(f.stem().string(), f.string());
  return scenes;
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
  for (const auto& [name, spec] : bench_scenes()) {
    benchmark::RegisterBenchmark(("build/" + name).c_str(), bm_build, spec)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
    for (const std::string& tracer : tracers)
      for (const bool diffuse : {false, true})
        benchmark::RegisterBenchmark(("trace/" + name + "/" + (diffuse ? "diffuse" : "primary") + "/" + tracer).c_str(),
                                     bm_trace, spec, diffuse, tracer)
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
    const raycoh::Size size = raycoh::bench_size();
    benchmark::AddCustomContext("embree", raycoh::embree_version());
    benchmark::AddCustomContext("image",
                                std::to_string(size.width) + "x" + std::to_string(size.height) + ", 8x8 tile order");
    raycoh::register_benchmarks();
  } catch (const raycoh::Error& e) {
    std::fprintf(stderr, "raycoh_bench: error: %s\n", e.what());
    return 2;
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  // Release the cached scene and tracer before static destruction, while Embree's device is still alive.
  raycoh::release_cache();
  return 0;
}
