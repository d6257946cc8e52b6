#include "core/params.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fmt/format.h>

#include "core/error.h"

namespace raycoh {

std::string join(const std::vector<std::string>& items, const std::string& sep) {
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) out += (i ? sep : "") + items[i];
  return out;
}

ParamSet::ParamSet(std::string owner, const std::string& text) : owner_(std::move(owner)) {
  size_t pos = 0;
  while (pos < text.size()) {
    size_t end = text.find(',', pos);
    if (end == std::string::npos) end = text.size();
    const std::string item = text.substr(pos, end - pos);
    pos = end + 1;
    if (item.empty()) continue;
    const size_t eq = item.find('=');
    if (eq == std::string::npos || eq == 0)
      throw Error(fmt::format("{}: parameter '{}' must be key=value", owner_, item));
    const std::string key = item.substr(0, eq);
    if (given_.count(key)) throw Error(fmt::format("{}: parameter '{}' given twice", owner_, key));
    given_[key] = item.substr(eq + 1);
  }
}

const std::string* ParamSet::take(const std::string& key) {
  auto it = given_.find(key);
  return it == given_.end() ? nullptr : &it->second;
}

template <class Int>
Int ParamSet::get_integer(const std::string& key, Int def, Int lo, Int hi) {
  Int value = def;
  if (const std::string* s = take(key)) {
    auto [p, ec] = std::from_chars(s->data(), s->data() + s->size(), value);
    if (ec != std::errc() || p != s->data() + s->size() || value < lo || value > hi)
      throw Error(fmt::format("{}: {}={} is not valid; expected an integer in [{}, {}]", owner_, key, *s, lo, hi));
  }
  used_.emplace_back(key, std::to_string(value));
  return value;
}

int ParamSet::get_int(const std::string& key, int def, int lo, int hi) { return get_integer(key, def, lo, hi); }

unsigned ParamSet::get_uint(const std::string& key, unsigned def, unsigned lo, unsigned hi) {
  return get_integer(key, def, lo, hi);
}

float ParamSet::get_float(const std::string& key, float def, float lo, float hi) {
  float value = def;
  if (const std::string* s = take(key)) {
    char* end = nullptr;
    value = std::strtof(s->c_str(), &end);
    if (s->empty() || end != s->c_str() + s->size() || !std::isfinite(value) || value < lo || value > hi)
      throw Error(fmt::format("{}: {}={} is not valid; expected a number in [{}, {}]", owner_, key, *s, lo, hi));
  }
  used_.emplace_back(key, fmt::format("{}", value));
  return value;
}

std::string ParamSet::get_choice(const std::string& key, const std::string& def,
                                 const std::vector<std::string>& choices) {
  std::string value = def;
  if (const std::string* s = take(key)) {
    if (std::find(choices.begin(), choices.end(), *s) == choices.end())
      throw Error(fmt::format("{}: {}={} is not valid; choose one of: {}", owner_, key, *s, join(choices)));
    value = *s;
  }
  used_.emplace_back(key, value);
  return value;
}

Vec3 ParamSet::get_vec3(const std::string& key, Vec3 def, float lo, float hi) {
  Vec3 value = def;
  if (const std::string* s = take(key)) {
    float c[3];
    const char* p = s->c_str();
    bool ok = true;
    for (int i = 0; i < 3 && ok; ++i) {
      char* end = nullptr;
      c[i] = std::strtof(p, &end);
      ok = end != p && std::isfinite(c[i]) && c[i] >= lo && c[i] <= hi && (*end == (i < 2 ? '/' : '\0'));
      p = end + 1;
    }
    if (!ok)
      throw Error(fmt::format("{}: {}={} is not valid; expected x/y/z with each in [{}, {}]", owner_, key, *s, lo, hi));
    value = {c[0], c[1], c[2]};
  }
  used_.emplace_back(key, fmt::format("{}/{}/{}", value.x, value.y, value.z));
  return value;
}

std::pair<int, int> ParamSet::get_size(const std::string& key, std::pair<int, int> def, int lo, int hi) {
  std::pair<int, int> value = def;
  if (const std::string* s = take(key)) value = parse_size(fmt::format("{}: {}", owner_, key), *s, lo, hi);
  used_.emplace_back(key, fmt::format("{}x{}", value.first, value.second));
  return value;
}

void ParamSet::finish() const {
  std::vector<std::string> known;
  for (const auto& [k, v] : used_) known.push_back(k);
  for (const auto& [k, v] : given_) {
    if (std::find(known.begin(), known.end(), k) == known.end())
      throw Error(fmt::format("{}: unknown parameter '{}'; valid parameters: {}", owner_, k,
                              known.empty() ? std::string("(none)") : join(known)));
  }
}

std::string ParamSet::canonical() const {
  std::string out;
  for (const auto& [k, v] : used_) out += (out.empty() ? "" : ",") + k + "=" + v;
  return out;
}

PluginSpec parse_plugin_spec(const std::string& text) {
  PluginSpec spec;
  const size_t colon = text.find(':');
  spec.name = text.substr(0, colon);
  if (colon != std::string::npos) spec.params = text.substr(colon + 1);
  return spec;
}

std::vector<PluginSpec> split_plugin_list(const std::string& text) {
  std::vector<PluginSpec> out;
  size_t pos = 0;
  while (pos <= text.size()) {
    size_t end = text.find(',', pos);
    if (end == std::string::npos) end = text.size();
    const std::string item = text.substr(pos, end - pos);
    pos = end + 1;
    if (item.empty()) continue;
    const bool continues = item.find('=') != std::string::npos &&
                           (item.find(':') == std::string::npos || item.find(':') > item.find('='));
    if (continues && !out.empty()) {
      out.back().params += (out.back().params.empty() ? "" : ",") + item;
    } else {
      out.push_back(parse_plugin_spec(item));
    }
  }
  return out;
}

int parse_int(const std::string& what, const std::string& text, int lo, int hi) {
  int v = 0;
  auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || p != text.data() + text.size() || v < lo || v > hi)
    throw Error(fmt::format("{}: '{}' is not valid; expected an integer in [{}, {}]", what, text, lo, hi));
  return v;
}

std::pair<int, int> parse_size(const std::string& what, const std::string& text, int lo, int hi) {
  const size_t x = text.find('x');
  int w = 0, h = 0;
  bool ok = x != std::string::npos;
  if (ok) {
    auto [p1, e1] = std::from_chars(text.data(), text.data() + x, w);
    auto [p2, e2] = std::from_chars(text.data() + x + 1, text.data() + text.size(), h);
    ok = e1 == std::errc() && e2 == std::errc() && p1 == text.data() + x && p2 == text.data() + text.size();
  }
  if (!ok || w < lo || w > hi || h < lo || h > hi)
    throw Error(fmt::format("{}: '{}' is not valid; expected WxH with each in [{}, {}]", what, text, lo, hi));
  return {w, h};
}

}  // namespace raycoh
