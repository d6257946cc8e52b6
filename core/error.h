// The one exception type for user mistakes (bad input files, unknown names, out-of-range parameters).
// main() catches it, prints "raycoh: error: <message>" on one line and exits with code 2. The message is made one
// line when the error is made (one_line): messages quote the user's input, and a file's line or a parameter may
// hold line breaks or other control characters.
#pragma once

#include <stdexcept>
#include <string>

namespace raycoh {

struct Error : std::runtime_error {
  explicit Error(const std::string& message);
  explicit Error(const char* message) : Error(std::string(message)) {}
};

// A failure of the device, not of the user's input: a CUDA call's error (an allocation, a launch, a fault in a
// kernel, a kernel past its time limit, a lost device). main() reports it on one line and exits 1; the experiment
// loops keep every finished row and name the scene, method and stage.
struct DeviceFault : Error {
  using Error::Error;
};

// text with line breaks and other control characters (tab aside) written as escapes: "\n", "\r", "\x1b".
std::string one_line(const std::string& text);

// Invariant check that stays on in Release builds; prints both sides of the failed condition.
[[noreturn]] void invariant_failed(const char* expr, const char* file, int line, const std::string& detail);

}  // namespace raycoh

#define RAYCOH_CHECK(cond, detail)                                                \
  do {                                                                            \
    if (!(cond)) ::raycoh::invariant_failed(#cond, __FILE__, __LINE__, (detail)); \
  } while (0)
