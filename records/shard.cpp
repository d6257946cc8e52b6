#include "records/shard.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>

#include "core/error.h"

namespace raycoh {

namespace {

uint64_t unit_hash(const std::string& key) {
  uint64_t h = 1469598103934665603ull;  // FNV-1a 64
  for (unsigned char c : key) {
    h ^= c;
    h *= 1099511628211ull;
  }
  h ^= h >> 30;  // splitmix64's finalizer: FNV's bits alone are poorly mixed for short, similar keys
  h *= 0xbf58476d1ce4e5b9ull;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebull;
  h ^= h >> 31;
  return h;
}

}  // namespace

std::vector<int> deal_units(const std::vector<std::string>& units, int count) {
  std::vector<std::pair<uint64_t, size_t>> order;  // (hash, index); equal hashes fall back to the name below
  for (size_t i = 0; i < units.size(); ++i) order.emplace_back(unit_hash(units[i]), i);
  std::sort(order.begin(), order.end(), [&](const auto& a, const auto& b) {
    return a.first != b.first ? a.first < b.first : units[a.second] < units[b.second];
  });
  std::vector<int> owner(units.size());
  for (size_t r = 0; r < order.size(); ++r) owner[order[r].second] = static_cast<int>(r % static_cast<size_t>(count));
  return owner;
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

std::string render_unit(const std::string& scene_spec, const std::string& method) {
  return scene_spec + '\x1f' + method;
}

std::vector<bool> owned_units(const std::vector<std::string>& units, const Shard& shard) {
  std::vector<bool> owned(units.size(), true);
  if (shard.whole()) return owned;
  const std::vector<int> owner = deal_units(units, shard.count);
  for (size_t u = 0; u < units.size(); ++u) owned[u] = owner[u] == shard.index;
  return owned;
}

}  // namespace raycoh
