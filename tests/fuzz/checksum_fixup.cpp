#include "tests/fuzz/checksum_fixup.h"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

namespace raycoh::fuzz {

uint64_t fnv1a(const void* data, size_t n, uint64_t h) {
  const auto* b = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < n; ++i) {
    h ^= b[i];
    h *= 1099511628211ull;
  }
  return h;
}

std::string hex16(uint64_t v) { return fmt::format("{:016x}", v); }

std::string fix_sidecar(const std::string& sidecar, const std::string& image, const std::string& half,
                        const std::string& key_json) {
  nlohmann::json side = nlohmann::json::parse(sidecar, nullptr, false);
  if (side.is_discarded() || !side.is_object()) return sidecar;
  if (!key_json.empty()) side["key"] = nlohmann::json::parse(key_json);
  side["image_fnv1a"] = hex16(fnv1a(image.data(), image.size()));
  if (side.contains("half_image")) side["half_image_fnv1a"] = hex16(fnv1a(half.data(), half.size()));
  side.erase("checksum");
  const std::string canonical = side.dump();
  side["checksum"] = hex16(fnv1a(canonical.c_str(), canonical.size() + 1));  // with the terminator, as raycoh
  return side.dump(2) + "\n";
}

std::string fix_part(const std::string& part) {
  const size_t eol = part.find('\n');
  if (eol == std::string::npos) return part;
  const nlohmann::json head = nlohmann::json::parse(part.substr(0, eol), nullptr, false);
  try {
    // Integers only, read wide (get<int> of a float out of range is undefined behaviour); anything else stays.
    const auto field = [](const nlohmann::json& j) {
      if (!j.is_number_integer()) throw nlohmann::json::type_error::create(302, "not an integer", &j);
      const int64_t v = j.get<int64_t>();
      return v < -(int64_t{1} << 40) || v > (int64_t{1} << 40) ? int64_t{-1} : v;
    };
    const int64_t w = field(head.at("width")), h = field(head.at("height"));
    const int64_t first = field(head.at("first_frame")), end = field(head.at("end_frame"));
    const int64_t block = field(head.at("key").at("frame_block"));
    const int64_t format = field(head.at("raycoh_reference_part"));
    if (w < 1 || h < 1 || w > 4096 || h > 4096 || w * h > 4096 || block < 1 || end <= first ||
        (end - first) / block > 64)
      return part;
    const size_t bytes = static_cast<size_t>(w * h) * (3 * sizeof(double) + 2 * sizeof(uint32_t));
    std::string out = part.substr(0, eol + 1);
    size_t at = eol + 1;
    uint64_t total = fnv1a(nullptr, 0);
    for (long b = 0; b < (end - first + block - 1) / block && at + bytes <= part.size(); ++b) {
      out += part.substr(at, bytes);
      total = fnv1a(part.data() + at, bytes, total);
      const uint64_t own = fnv1a(part.data() + at, bytes);
      at += bytes;
      if (format < 2) continue;
      const size_t line_end = part.find('\n', at);
      if (line_end == std::string::npos) break;
      std::string line = part.substr(at, line_end - at);
      const size_t h1 = line.find(' ', line.find(' ') + 1);
      const size_t h2 = h1 == std::string::npos ? std::string::npos : line.find(' ', h1 + 1);
      if (h2 != std::string::npos) line = line.substr(0, h1 + 1) + hex16(own) + line.substr(h2);
      out += line + "\n";
      at = line_end + 1;
    }
    const size_t end_line = part.find('\n', at);
    if (at < part.size() && part.compare(at, 4, "end ") == 0) {
      out += "end " + hex16(total) + (end_line == std::string::npos ? "" : part.substr(end_line));
    } else {
      out += part.substr(std::min(at, part.size()));
    }
    return out;
  } catch (const nlohmann::json::exception&) {
    return part;
  }
}

}  // namespace raycoh::fuzz
