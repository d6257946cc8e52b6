#include "core/fault_injection.h"

#include <cstdlib>
#include <mutex>

#include "core/error.h"

namespace raycoh {
namespace {

struct Injection {
  std::mutex mutex;
  bool loaded = false;
  std::string site;
  long at = 0, seen = 0;
};

Injection& injection() {
  static Injection i;
  return i;
}

// Parses "<site>:<n>" into i (caller holds the lock).
void configure(Injection& i, const std::string& spec) {
  i.loaded = true;
  i.site.clear();
  i.at = i.seen = 0;
  if (spec.empty()) return;
  const size_t colon = spec.rfind(':');
  char* end = nullptr;
  const long n = colon == std::string::npos ? 0 : std::strtol(spec.c_str() + colon + 1, &end, 10);
  if (colon == 0 || colon == std::string::npos || n < 1 || *end != '\0')
    throw Error("RAYCOH_INJECT_FAULT=" + spec + ": expected <site>:<n>, n >= 1 (e.g. cudaMalloc:1 or trace:3)");
  i.site = spec.substr(0, colon);
  i.at = n;
}

}  // namespace

bool inject_fault(const std::string& site) {
  Injection& i = injection();
  std::lock_guard<std::mutex> lock(i.mutex);
  if (!i.loaded) {
    const char* env = std::getenv("RAYCOH_INJECT_FAULT");
    configure(i, env ? env : "");
  }
  if (i.site.empty() || site.find(i.site) == std::string::npos) return false;
  return ++i.seen == i.at;
}

void set_fault_injection(const std::string& spec) {
  Injection& i = injection();
  std::lock_guard<std::mutex> lock(i.mutex);
  configure(i, spec);
}

}  // namespace raycoh
