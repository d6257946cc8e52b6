#include "core/error.h"

#include <cstdio>
#include <cstdlib>

namespace raycoh {

void invariant_failed(const char* expr, const char* file, int line, const std::string& detail) {
  std::fprintf(stderr, "raycoh: internal invariant failed: %s (%s:%d): %s\n", expr, file, line, detail.c_str());
  std::abort();
}

}  // namespace raycoh
