#include "core/error.h"

#include <cstdio>
#include <cstdlib>
#include <string>

namespace raycoh {

Error::Error(const std::string& message) : std::runtime_error(one_line(message)) {}

std::string one_line(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if ((u < 0x20 && c != '\t') || u == 0x7f) {
      char hex[5];
      std::snprintf(hex, sizeof hex, "\\x%02x", u);
      out += hex;
    } else {
      out += c;
    }
  }
  return out;
}

void invariant_failed(const char* expr, const char* file, int line, const std::string& detail) {
  std::fprintf(stderr, "raycoh: internal invariant failed: %s (%s:%d): %s\n", expr, file, line, detail.c_str());
  std::abort();
}

}  // namespace raycoh
