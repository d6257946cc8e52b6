// Helpers of the fuzz targets: a private scratch folder, files written from the input, inputs of several files,
// and the check of the reader's answer (fuzz_targets.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "scenes/scene.h"

namespace raycoh::fuzz {

// This process's scratch folder (created once, emptied on request, removed at exit).
const std::string& scratch_dir();
// Removes everything inside the scratch folder (each run starts from an empty folder).
void clear_scratch();

// The built-in cornell scene and its BVH, made once (the targets that need a scene to make plugins or references).
struct SmallScene {
  Scene scene = load_scene("cornell");
  Bvh bvh = build_bvh(scene);
};
const SmallScene& small_scene();
// Writes bytes to scratch_dir()/name and returns the path.
std::string write_scratch(const std::string& name, const std::string& bytes);

// An input holding several files: the parts between separator lines "\n--raycoh-fuzz-split--\n" (at most
// `max_parts`; the rest stays in the last part).
constexpr const char* kSplit = "\n--raycoh-fuzz-split--\n";
std::vector<std::string> split_input(const uint8_t* data, size_t size, size_t max_parts);

// Runs `body`; a raycoh::Error is the reader's answer and must be one non-empty line containing `names` (the file
// name or text the user gave); anything else escaping `body` is left to propagate (libFuzzer reports it).
template <class F>
void expect_clean(const std::string& names, F&& body);
void check_error_message(const std::string& message, const std::string& names);

}  // namespace raycoh::fuzz

#include "core/error.h"

template <class F>
void raycoh::fuzz::expect_clean(const std::string& names, F&& body) {
  try {
    body();
  } catch (const raycoh::Error& e) {
    check_error_message(e.what(), names);
  }
}
