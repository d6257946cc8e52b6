// The one exception type for user mistakes (bad input files, unknown names, out-of-range parameters).
// main() catches it, prints "raycoh: error: <message>" on one line and exits with code 2.
#pragma once

#include <stdexcept>
#include <string>

namespace raycoh {

struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Invariant check that stays on in Release builds; prints both sides of the failed condition.
[[noreturn]] void invariant_failed(const char* expr, const char* file, int line, const std::string& detail);

}  // namespace raycoh

#define RAYCOH_CHECK(cond, detail)                                                \
  do {                                                                            \
    if (!(cond)) ::raycoh::invariant_failed(#cond, __FILE__, __LINE__, (detail)); \
  } while (0)
