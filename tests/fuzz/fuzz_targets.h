// The fuzz targets: one function per reader of outside input, fed raw bytes. The same functions run under
// libFuzzer (fuzz_main.cpp, scripts/fuzz, clang builds with RAYCOH_FUZZ=ON) and, over the inputs kept in
// tests/fuzz/regressions/<target>/, in the ordinary test suite (tests/fuzz_regressions_test.cpp), so every input
// that once crashed stays checked without a fuzzer.
//
// What a target accepts from the reader: a result, or raycoh::Error whose message is one non-empty line naming the
// input (its file name or its text). Anything else — another exception type, a message of several lines or one that
// does not name the input, a crash, a sanitizer report, a huge allocation, a hang — is a finding: FuzzFinding is
// thrown (libFuzzer aborts on it, the regression test fails).
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace raycoh::fuzz {

struct FuzzFinding : std::logic_error {
  using std::logic_error::logic_error;
};

using TargetFn = void (*)(const uint8_t* data, size_t size);
struct Target {
  const char* name;
  const char* reader;  // what it covers, for `scripts/fuzz --list` and the docs
  TargetFn run;
};
// Every target, in the order scripts/fuzz runs them.
const std::vector<Target>& targets();
const Target* find_target(const std::string& name);

// The targets (one file each, tests/fuzz/<name>.cpp or grouped by reader family).
void fuzz_gltf(const uint8_t* data, size_t size);
void fuzz_obj(const uint8_t* data, size_t size);
void fuzz_scene_spec(const uint8_t* data, size_t size);
void fuzz_plugin_params(const uint8_t* data, size_t size);
void fuzz_csv_resume(const uint8_t* data, size_t size);
void fuzz_shard_merge(const uint8_t* data, size_t size);
void fuzz_reference_cache(const uint8_t* data, size_t size);
void fuzz_reference_parts(const uint8_t* data, size_t size);
void fuzz_compare_image(const uint8_t* data, size_t size);
void fuzz_option_values(const uint8_t* data, size_t size);

}  // namespace raycoh::fuzz
