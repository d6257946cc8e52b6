#include "harness/tune/tune_space.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <sstream>

#include "core/error.h"
#include "generators/generator.h"

namespace raycoh {

namespace {

const std::vector<std::string> kAxes{"tile", "k", "order", "hybrid", "frame"};
// Each axis's values are those of ours' parameter table (contiguous has the same table): its row is the one rule.
const ParamSpec& ours_row(const std::string& param) {
  const ParamSpec* row = generator_param_row("ours", param);
  if (!row) throw Error(fmt::format("internal error: ours has no parameter '{}'", param));
  return *row;
}

std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(text);
  while (std::getline(in, item, sep))
    if (!item.empty()) out.push_back(item);
  return out;
}

std::vector<std::string> choices(const std::string& axis, const std::vector<std::string>& values,
                                 const std::vector<std::string>& valid) {
  for (const std::string& v : values)
    if (std::find(valid.begin(), valid.end(), v) == valid.end())
      throw Error(fmt::format("--space {}={}: unknown value; valid: {}", axis, v, join(valid)));
  return values;
}

double parse_ratio(const std::string& metric, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !(v >= 1.0) || v > 100.0)
    throw Error(fmt::format("--budget {}={}: expected a ratio to noopt's error in [1, 100]", metric, text));
  return v;
}

}  // namespace

std::string TuneSetting::spec() const {
  return fmt::format("{}:tile={}x{},k={},order={},hybrid={},frame={}", generator, tile_w, tile_h, k, order, hybrid,
                     frame);
}

std::string TuneSetting::image_spec() const {
  return fmt::format("{}:tile={}x{},k={},hybrid={},frame={}", generator, tile_w, tile_h, k, hybrid, frame);
}

TuneSetting paper_setting(const std::string& generator) {
  TuneSetting s;
  s.generator = generator;
  return s;
}

TuneSpace parse_tune_space(const std::string& text) {
  TuneSpace s;
  const std::vector<std::string> axes = split(text, ' ');
  if (axes.empty()) throw Error("--space: empty; expected axes like tile=8x8,16x8 k=8,16 order=tile,group");
  for (const std::string& axis : axes) {
    const size_t eq = axis.find('=');
    const std::string name = axis.substr(0, eq);
    if (eq == std::string::npos || std::find(kAxes.begin(), kAxes.end(), name) == kAxes.end())
      throw Error(fmt::format("--space '{}': expected AXIS=V1,V2,... with AXIS one of {}", axis, join(kAxes)));
    const std::vector<std::string> values = split(axis.substr(eq + 1), ',');
    if (values.empty()) throw Error(fmt::format("--space {}: no values", axis));
    if (name == "tile") {
      s.tiles.clear();
      for (const std::string& v : values) s.tiles.push_back(parse_size("--space tile", v, 1, kMaxTileSide));
    } else if (name == "k") {
      s.ks.clear();
      const ParamSpec& k = ours_row("k");
      for (const std::string& v : values)
        s.ks.push_back(parse_int("--space k", v, static_cast<int>(k.lo), static_cast<int>(k.hi)));
    } else if (name == "order") {
      s.orders = choices(name, values, ours_row("order").choices);
    } else if (name == "hybrid") {
      s.hybrids = choices(name, values, ours_row("hybrid").choices);
    } else {
      s.frames = choices(name, values, ours_row("frame").choices);
    }
  }
  for (const auto& tile : s.tiles) check_tile("--space", tile);
  return s;
}

std::string describe(const TuneSpace& s) {
  std::vector<std::string> tiles, ks;
  for (const auto& [w, h] : s.tiles) tiles.push_back(fmt::format("{}x{}", w, h));
  for (int k : s.ks) ks.push_back(std::to_string(k));
  return fmt::format("tile={} k={} order={} hybrid={} frame={}", join(tiles, ","), join(ks, ","), join(s.orders, ","),
                     join(s.hybrids, ","), join(s.frames, ","));
}

std::vector<TuneSetting> expand(const TuneSpace& space, const std::string& generator) {
  std::vector<TuneSetting> out;
  for (const auto& [w, h] : space.tiles)
    for (int k : space.ks) {
      if (k > w * h) continue;  // not a grouping of the tile: left out, as sweep leaves the cell empty
      for (const std::string& order : space.orders)
        for (const std::string& hybrid : space.hybrids)
          for (const std::string& frame : space.frames) out.push_back({generator, w, h, k, order, hybrid, frame});
    }
  if (out.empty()) throw Error("--space: every K exceeds its tile's pixels; no setting to measure");
  return out;
}

TuneBudget parse_tune_budget(const std::string& text) {
  TuneBudget b{0, 0, 0, false};
  const std::vector<std::string> items = split(text, ',');
  if (items.empty()) throw Error("--budget: empty; expected e.g. ds8=1.05,flip=1.05,bias=none");
  for (const std::string& item : items) {
    const size_t eq = item.find('=');
    const std::string metric = item.substr(0, eq), value = eq == std::string::npos ? "" : item.substr(eq + 1);
    if (metric == "ds8" && eq != std::string::npos) {
      b.ds8_paper = value == "paper";
      b.ds8 = b.ds8_paper ? 1 : parse_ratio(metric, value);
    } else if (metric == "rel" && eq != std::string::npos) {
      b.rel_paper = value == "paper";
      b.rel = b.rel_paper ? 1 : parse_ratio(metric, value);
    } else if (metric == "flip" && eq != std::string::npos) {
      b.flip_paper = value == "paper";
      b.flip = b.flip_paper ? 1 : parse_ratio(metric, value);
    } else if (metric == "bias" && (value == "none" || value == "any")) {
      b.no_bias = value == "none";
    } else {
      throw Error(
          fmt::format("--budget '{}': expected ds8=R, rel=R, flip=R (R a ratio to noopt in [1, 100]) or "
                      "bias=none|any",
                      item));
    }
  }
  return b;
}

std::string describe(const TuneBudget& b) {
  std::vector<std::string> parts;
  auto bound = [](double v, bool paper) { return paper ? std::string("paper") : fmt::format("{}", v); };
  if (b.ds8 > 0) parts.push_back("ds8=" + bound(b.ds8, b.ds8_paper));
  if (b.rel > 0) parts.push_back("rel=" + bound(b.rel, b.rel_paper));
  if (b.flip > 0) parts.push_back("flip=" + bound(b.flip, b.flip_paper));
  parts.push_back(b.no_bias ? "bias=none" : "bias=any");
  return join(parts, ",");
}

}  // namespace raycoh
