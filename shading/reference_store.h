// The reference cache's shared pieces (shading/reference.cpp: entries, get_reference; shading/reference_parts.cpp:
// frame shards and their part files). Internal to shading/.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "generators/generator.h"
#include "plugins/tracer_registry.h"
#include "shading/reference.h"

namespace raycoh::reference_store {

namespace fs = std::filesystem;

struct Fnv1a {
  uint64_t h = 1469598103934665603ull;
  void add(const void* data, size_t n) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) {
      h ^= b[i];
      h *= 1099511628211ull;
    }
  }
  void add(const std::string& s) { add(s.data(), s.size() + 1); }  // with the terminator, so "ab","c" != "a","bc"
  void add_u64(uint64_t v) { add(&v, sizeof v); }
};

// The cache entry of a key: folder, file stem "<scene>-<digest>", image and sidecar paths.
struct Entry {
  fs::path dir, image, sidecar;
  std::string stem;
  uint64_t digest = 0;
};
Entry entry_of(const std::string& stem_prefix, const std::string& key, const std::string& cache_dir);

// A file-name-safe form of a scene name.
std::string safe_name(const std::string& name);
// An int field of a file's JSON, as nlohmann's get<int> but refusing (type_error) what is not an integer in int's
// range.
int int_field(const nlohmann::json& j);
void create_cache_dir(const fs::path& dir);
// This machine's name for a part's block lines and a sidecar's render hosts (no blanks).
std::string host_name();
// The request's settings, frames and frame block in range, or Error.
void check_request(const ReferenceRequest& r);
// Writes the image (and its half), then the sidecar (the old sidecar removed first). Call with the entry's lock held.
// `extra`: more sidecar fields (a combined entry's parts).
void store_entry(const Entry& e, const std::string& key, const Reference& ref,
                 const nlohmann::json& extra = nlohmann::json::object());

// Renders frames [range.first, range.end) block by block (blocks of r.frame_block counted from frame 0), each
// into a fresh accumulator handed to on_block in frame order.
template <class OnBlock>
double render_blocks(const Scene& scene, const Bvh& bvh, const ReferenceRequest& r, FrameRange range,
                     OnBlock&& on_block) {
  // The CPU path tracer (NoOpt, r.tracer), or the device's frames (r.make_renderer).
  FrameRenderer render = r.make_renderer ? r.make_renderer() : FrameRenderer();
  std::unique_ptr<Tracer> tracer;
  std::unique_ptr<Generator> generator;
  std::unique_ptr<PathTracer> pt;
  if (!render) {
    tracer = make_tracer(r.tracer, scene, bvh);
    generator = make_generator({"noopt", ""});
    pt = std::make_unique<PathTracer>(scene, *tracer, *generator, r.settings);
    render = [&pt](uint32_t f, Accumulator& acc) { pt->render_frame(f, acc); };
  }
  const auto t0 = std::chrono::steady_clock::now();
  for (int b = range.first; b < range.end; b += r.frame_block) {
    Accumulator block(r.settings.width, r.settings.height);
    const int end = std::min(range.end, b + r.frame_block);
    for (int f = b; f < end; ++f) {
      render(static_cast<uint32_t>(f), block);
      if (r.progress) r.progress(f - range.first + 1, range.end - range.first);
    }
    on_block(block, b);
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace raycoh::reference_store
