// Helpers shared by the tests: where the shared scenes are, temporary files, running the CLI.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.h"

namespace raycoh::test {

// Elements of a and b whose bytes differ (every element when the sizes differ): the bit-for-bit comparisons of the
// device tests (types without padding bytes).
template <class T>
size_t differing(const std::vector<T>& a, const std::vector<T>& b) {
  if (a.size() != b.size()) return std::max(a.size(), b.size());
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i) n += std::memcmp(&a[i], &b[i], sizeof(T)) != 0;
  return n;
}

// $RAYCOH_SCENES, else RAYCOH_SHARED_SCENES (CMake; default: shared/scenes beside the repository); empty when
// absent.
inline std::filesystem::path shared_scenes_dir() {
  if (const char* env = std::getenv("RAYCOH_SCENES")) return env;
  std::filesystem::path p = RAYCOH_SHARED_SCENES;
  return std::filesystem::exists(p) ? p : std::filesystem::path{};
}

// $RAYCOH_GLTF_SAMPLES, else gltf-samples beside the shared scenes folder; empty when absent.
inline std::filesystem::path gltf_samples_dir() {
  if (const char* env = std::getenv("RAYCOH_GLTF_SAMPLES")) return env;
  const std::filesystem::path p = std::filesystem::path(RAYCOH_SHARED_SCENES).parent_path() / "gltf-samples";
  return std::filesystem::exists(p) ? p : std::filesystem::path{};
}

// Every .glb under the shared scenes directory, sorted by name.
std::vector<std::filesystem::path> shared_scene_files();

// A fresh directory under the system temp dir, removed at process exit is not needed: tests use unique names.
std::filesystem::path temp_dir(const std::string& name);

void write_file(const std::filesystem::path& path, const std::string& bytes);

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};
// Runs the raycoh binary with the given argument string (shell syntax).
CommandResult run_raycoh(const std::string& args);
// Runs a shell script in which $R is the raycoh binary (for limits, signals and background runs); stdout and
// stderr together; exit_code is the script's (-1 when a signal ended the shell).
CommandResult run_shell(const std::string& script);

// Runs fn, which should throw raycoh::Error; returns the message, or "no error".
template <typename Fn>
std::string error_of(Fn fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace raycoh::test
