// What the benchmark programs share: the image size, the scenes, and one frame of the real pipeline (primary
// rays in 8x8 tile order through the `cpu` tracer, G-buffer, batches made by the registered generators), so the
// benchmarks measure the batches the harness measures.
//   RAYCOH_BENCH_SIZE=WxH   image size (each program has its own default)
//   RAYCOH_SCENES=DIR       folder of the shared scenes (default: shared/scenes beside the repository)
#pragma once

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/params.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "generators/primary.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "tracers/tracer.h"

namespace raycoh::bench {

constexpr uint32_t kSeed = 1;

inline std::pair<int, int> image_size(std::pair<int, int> fallback) {
  if (const char* env = std::getenv("RAYCOH_BENCH_SIZE")) return parse_size("RAYCOH_BENCH_SIZE", env, 1, 16384);
  return fallback;
}

inline std::filesystem::path scenes_dir() {
  if (const char* env = std::getenv("RAYCOH_SCENES")) return env;
  return RAYCOH_SHARED_SCENES;
}

// (name, spec): the built-in scenes, then every .glb of the shared scenes (or only those named in `only`).
inline std::vector<std::pair<std::string, std::string>> scenes(const std::vector<std::string>& only = {}) {
  std::vector<std::pair<std::string, std::string>> out = {{"cornell", "cornell"}, {"voxels", "voxels"}};
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  if (std::filesystem::is_directory(scenes_dir(), ec))
    for (const auto& entry : std::filesystem::recursive_directory_iterator(scenes_dir(), ec))
      if (entry.path().extension() == ".glb") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  for (const auto& f : files)
    if (only.empty() || std::find(only.begin(), only.end(), f.stem().string()) != only.end())
      out.emplace_back(f.stem().string(), f.string());
  return out;
}

// One frame of one scene; batches are made on first use and kept by generator spec.
struct Frame {
  std::string spec;
  Scene scene;
  Bvh bvh;
  PixelRays primary;
  GBuffer gbuffer;
  std::map<std::string, RayBatch> batches;

  const RayBatch& batch(const std::string& generator) {
    auto it = batches.find(generator);
    if (it != batches.end()) return it->second;
    RayBatch b;
    GenerationStats stats;
    make_generator(parse_plugin_spec(generator))->generate(scene, gbuffer, kSeed, b, stats);
    return batches[generator] = std::move(b);
  }
};

// The one frame held at a time (benchmarks are registered scene by scene, so each scene loads once).
inline Frame& frame(const std::string& spec, std::pair<int, int> size) {
  static std::unique_ptr<Frame> held;
  if (held && held->spec == spec) return *held;
  held.reset();
  auto f = std::make_unique<Frame>();
  f->spec = spec;
  f->scene = load_scene(spec);
  f->bvh = build_bvh(f->scene);
  const auto order = make_pixel_order(size.first, size.second, RayOrder::Tile, 8, 8);
  FirstHits first =
      first_hits(f->scene, *make_tracer({"cpu", ""}, f->scene, f->bvh), size.first, size.second, order, kSeed, 0, true);
  f->primary = std::move(first.primary);
  f->gbuffer = std::move(first.gbuffer);
  held = std::move(f);
  return *held;
}

}  // namespace raycoh::bench
