#include "tests/fuzz/fuzz_util.h"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "tests/fuzz/fuzz_targets.h"

namespace raycoh::fuzz {

namespace fs = std::filesystem;

namespace {

struct Scratch {
  std::string dir;
  // In memory (/dev/shm) where there is one: the CSV writer and the reference cache fsync every file they finish,
  // which on a disk costs milliseconds per input and would be most of a target's time.
  Scratch() {
    std::error_code ec;
    const fs::path base = fs::is_directory("/dev/shm", ec) && ::access("/dev/shm", W_OK) == 0
                              ? fs::path("/dev/shm")
                              : fs::temp_directory_path();
    dir = (base / ("raycoh-fuzz-" + std::to_string(::getpid()))).string();
    fs::create_directories(dir);
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

}  // namespace

const std::string& scratch_dir() {
  static const Scratch scratch;
  return scratch.dir;
}

const SmallScene& small_scene() {
  static const SmallScene s;
  return s;
}

void clear_scratch() {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(scratch_dir(), ec)) fs::remove_all(e.path(), ec);
}

std::string write_scratch(const std::string& name, const std::string& bytes) {
  const std::string path = scratch_dir() + "/" + name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw FuzzFinding("cannot write the scratch file " + path);
  return path;
}

std::vector<std::string> split_input(const uint8_t* data, size_t size, size_t max_parts) {
  const std::string all(reinterpret_cast<const char*>(data), size), sep(kSplit);
  std::vector<std::string> parts;
  size_t at = 0;
  while (parts.size() + 1 < max_parts) {
    const size_t next = all.find(sep, at);
    if (next == std::string::npos) break;
    parts.push_back(all.substr(at, next - at));
    at = next + sep.size();
  }
  parts.push_back(all.substr(at));
  return parts;
}

void check_error_message(const std::string& message, const std::string& names) {
  if (message.empty()) throw FuzzFinding("raycoh::Error with an empty message");
  if (message.find_first_of("\n\r") != std::string::npos)
    throw FuzzFinding("raycoh::Error of more than one line: " + message);
  // Error escapes control characters in what it quotes (core/error.h one_line): look for the name as printed.
  if (!names.empty() && message.find(one_line(names)) == std::string::npos)
    throw FuzzFinding("raycoh::Error that does not name the input '" + names + "': " + message);
}

const std::vector<Target>& targets() {
  static const std::vector<Target> all = {
      {"gltf", "glTF 2.0 .gltf/.glb with textures (scenes/gltf_*.cpp, load_gltf; images through oiio/)", fuzz_gltf},
      {"obj", "Wavefront OBJ + MTL (scenes/obj_loader.cpp, load_obj)", fuzz_obj},
      {"scene_spec", "scene specs with parameters: built-ins and file:key=value (scenes/, load_scene)",
       fuzz_scene_spec},
      {"plugin_params", "generator, encoder and tracer specs and parameter strings (core/params.cpp, registries)",
       fuzz_plugin_params},
      {"csv_resume", "an earlier run's CSV read back for resume (records/record_csv.h)", fuzz_csv_resume},
      {"shard_merge", "shard CSV files of `raycoh merge` (harness/merge.cpp)", fuzz_shard_merge},
      {"reference_cache", "reference cache entry: sidecar JSON + image (shading/reference.cpp get_reference)",
       fuzz_reference_cache},
      {"reference_parts", "part files of sharded references (shading/reference.cpp combine_reference_parts)",
       fuzz_reference_parts},
      {"compare_image", "PFM and EXR images read by `compare` (shading/image*.cpp read_image, oiio/)",
       fuzz_compare_image},
      {"option_values", "option values the commands parse: --res, --shard, --crop, --time, --scenes, --tone-map, ...",
       fuzz_option_values},
  };
  return all;
}

const Target* find_target(const std::string& name) {
  for (const Target& t : targets())
    if (name == t.name) return &t;
  return nullptr;
}

}  // namespace raycoh::fuzz
