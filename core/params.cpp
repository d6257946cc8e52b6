#include "core/params.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>

#include "core/error.h"

namespace raycoh {

std::string join(const std::vector<std::string>& items, const std::string& sep) {
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) out += (i ? sep : "") + items[i];
  return out;
}

ParamSpec int_param(std::string name, int def, int lo, int hi, std::string doc) {
  return {std::move(name), ParamType::Int, std::to_string(def), double(lo), double(hi), {}, std::move(doc)};
}

ParamSpec uint_param(std::string name, unsigned def, unsigned lo, unsigned hi, std::string doc) {
  return {std::move(name), ParamType::Uint, std::to_string(def), double(lo), double(hi), {}, std::move(doc)};
}

ParamSpec float_param(std::string name, float def, float lo, float hi, std::string doc) {
  return {std::move(name), ParamType::Float, fmt::format("{}", def), double(lo), double(hi), {}, std::move(doc)};
}

ParamSpec choice_param(std::string name, std::string def, std::vector<std::string> choices, std::string doc) {
  return {std::move(name), ParamType::Choice, std::move(def), 0, 0, std::move(choices), std::move(doc)};
}

ParamSpec size_param(std::string name, std::pair<int, int> def, int lo, int hi, std::string doc) {
  return {std::move(name), ParamType::Size, fmt::format("{}x{}", def.first, def.second), double(lo), double(hi), {},
          std::move(doc)};
}

namespace {

const char* type_name(ParamType type) {
  switch (type) {
    case ParamType::Int:
      return "int";
    case ParamType::Uint:
      return "uint";
    case ParamType::Float:
      return "float";
    case ParamType::Choice:
      return "choice";
    case ParamType::Size:
      return "WxH";
  }
  return "?";
}

// Ranges print as the reader's error messages do: ints as ints, floats in shortest form.
std::string range_text(const ParamSpec& s) {
  switch (s.type) {
    case ParamType::Int:
      return fmt::format("[{}, {}]", int(s.lo), int(s.hi));
    case ParamType::Uint:
      return fmt::format("[{}, {}]", unsigned(s.lo), unsigned(s.hi));
    case ParamType::Float:
      return fmt::format("[{}, {}]", float(s.lo), float(s.hi));
    case ParamType::Choice:
      return join(s.choices, " | ");
    case ParamType::Size:
      return fmt::format("[{}, {}] each", int(s.lo), int(s.hi));
  }
  return {};
}

}  // namespace

std::string format_param_table(const ParamTable& table, const std::string& indent) {
  if (table.empty()) return indent + "(no parameters)\n";
  size_t widths[4] = {0, 0, 0, 0};
  for (const ParamSpec& s : table) {
    widths[0] = std::max(widths[0], s.name.size());
    widths[1] = std::max(widths[1], std::string(type_name(s.type)).size());
    widths[2] = std::max(widths[2], s.def.size());
    widths[3] = std::max(widths[3], range_text(s).size());
  }
  std::string out;
  for (const ParamSpec& s : table)
    out += fmt::format("{}{:<{}}  {:<{}}  {:<{}}  {:<{}}  {}\n", indent, s.name, widths[0], type_name(s.type),
                       widths[1], s.def, widths[2], range_text(s), widths[3], s.doc);
  return out;
}

std::string default_params(const ParamTable& table) {
  std::string out;
  for (const ParamSpec& s : table) out += (out.empty() ? "" : ",") + s.name + "=" + s.def;
  return out;
}

std::string param_summary(const ParamTable& table) {
  std::vector<std::string> items;
  for (const ParamSpec& s : table) items.push_back(s.name + "=" + s.def + " (" + range_text(s) + ")");
  return items.empty() ? "(no parameters)" : join(items);
}

ParamSet::ParamSet(std::string owner, const std::string& text, const ParamTable& table)
    : ParamSet(std::move(owner), text) {
  table_ = &table;
}

const ParamSpec& ParamSet::row(const std::string& key, ParamType type) const {
  if (table_)
    for (const ParamSpec& s : *table_)
      if (s.name == key && s.type == type) return s;
  throw Error(fmt::format("internal error: {} reads '{}' as a {}, which its parameter table does not declare", owner_,
                          key, type_name(type)));
}

int ParamSet::get_int(const std::string& key) { return get_int_at_most(key, int(row(key, ParamType::Int).hi)); }

int ParamSet::get_int_at_most(const std::string& key, int at_most) {
  const ParamSpec& s = row(key, ParamType::Int);
  // Only a given value is checked against at_most, as before tables: the default stands even when it is larger.
  const int def = parse_int(owner_ + ": default of " + key, s.def, int(s.lo), int(s.hi));
  return get_int(key, def, int(s.lo), std::min(int(s.hi), at_most));
}

unsigned ParamSet::get_uint(const std::string& key) {
  const ParamSpec& s = row(key, ParamType::Uint);
  const unsigned def = static_cast<unsigned>(std::stoul(s.def));
  return get_uint(key, def, unsigned(s.lo), unsigned(s.hi));
}

float ParamSet::get_float(const std::string& key) {
  const ParamSpec& s = row(key, ParamType::Float);
  return get_float(key, std::strtof(s.def.c_str(), nullptr), float(s.lo), float(s.hi));
}

std::string ParamSet::get_choice(const std::string& key) {
  const ParamSpec& s = row(key, ParamType::Choice);
  return get_choice(key, s.def, s.choices);
}

std::pair<int, int> ParamSet::get_size(const std::string& key) {
  const ParamSpec& s = row(key, ParamType::Size);
  return get_size(key, parse_size(owner_ + ": default of " + key, s.def, int(s.lo), int(s.hi)), int(s.lo), int(s.hi));
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

// Records a value read; a plugin reads each of its parameters once (a second read would repeat it in params()).
void ParamSet::use(const std::string& key, std::string value) {
  for (const auto& [k, v] : used_)
    if (k == key) throw Error(fmt::format("internal error: {} reads its parameter '{}' twice", owner_, key));
  used_.emplace_back(key, std::move(value));
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
  use(key, std::to_string(value));
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
  use(key, fmt::format("{}", value));
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
  use(key, value);
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
  use(key, fmt::format("{}/{}/{}", value.x, value.y, value.z));
  return value;
}

std::pair<int, int> ParamSet::get_size(const std::string& key, std::pair<int, int> def, int lo, int hi) {
  std::pair<int, int> value = def;
  if (const std::string* s = take(key)) value = parse_size(fmt::format("{}: {}", owner_, key), *s, lo, hi);
  use(key, fmt::format("{}x{}", value.first, value.second));
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
  // A row the plugin never reads would be listed but ignored: a programming error, caught by every run.
  if (table_)
    for (const ParamSpec& s : *table_)
      if (std::find(known.begin(), known.end(), s.name) == known.end())
        throw Error(fmt::format("internal error: {} declares parameter '{}' but never reads it", owner_, s.name));
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
    const bool continues =
        item.find('=') != std::string::npos && (item.find(':') == std::string::npos || item.find(':') > item.find('='));
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
