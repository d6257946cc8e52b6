#include "harness/shard.h"

#include <fmt/format.h>

#include <cstdlib>

#include "core/error.h"

namespace raycoh {

int Shard::owner(const std::string& unit_key, int count) {
  uint64_t h = 1469598103934665603ull;  // FNV-1a 64
  for (unsigned char c : unit_key) {
    h ^= c;
    h *= 1099511628211ull;
  }
  h ^= h >> 30;  // splitmix64 finalizer: FNV's low bits alone are poorly mixed for short, similar keys
  h *= 0xbf58476d1ce4e5b9ull;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebull;
  h ^= h >> 31;
  return static_cast<int>(h % static_cast<uint64_t>(count));
}

Shard parse_shard(const std::string& option, const std::string& text) {
  const auto bad = [&] {
    return Error(fmt::format("{} {}: expected I/N with N in [1, {}] and I in [0, N) (e.g. 0/4 ... 3/4)", option, text,
                             kMaxShards));
  };
  const size_t slash = text.find('/');
  if (slash == std::string::npos) throw bad();
  const std::string i_text = text.substr(0, slash), n_text = text.substr(slash + 1);
  const auto number = [&](const std::string& s) {
    if (s.empty() || s.size() > 6 || s.find_first_not_of("0123456789") != std::string::npos) throw bad();
    return std::atoi(s.c_str());
  };
  Shard s;
  s.index = number(i_text);
  s.count = number(n_text);
  if (s.count < 1 || s.count > kMaxShards || s.index >= s.count) throw bad();
  return s;
}

std::string experiment_unit(const std::string& scene, int frame, const std::string& method) {
  return scene + '\x1f' + std::to_string(frame) + '\x1f' + method;
}

}  // namespace raycoh
