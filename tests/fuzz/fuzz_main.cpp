// libFuzzer entry of one target (RAYCOH_FUZZ_TARGET, set per executable in tests/fuzz/CMakeLists.txt). A
// FuzzFinding (fuzz_targets.h) aborts, which libFuzzer reports as a crash and keeps the input.
#include <cstdio>
#include <cstdlib>

#include "tests/fuzz/fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    raycoh::fuzz::RAYCOH_FUZZ_TARGET(data, size);
  } catch (const raycoh::fuzz::FuzzFinding& f) {
    std::fprintf(stderr, "fuzz finding: %s\n", f.what());
    std::abort();
  }
  return 0;
}
