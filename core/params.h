// Checked parameter sets for plugins ("ours:tile=8x8,k=8", "voxels:size=96", "embree:mode=packet16").
//
// A plugin asks for each parameter with its default and valid range; finish() then rejects any key that was
// given but never asked for, naming the valid keys. canonical() is the full, defaulted set that ran, which
// every result row records.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/vec.h"

namespace raycoh {

class ParamSet {
 public:
  ParamSet() = default;
  // owner names the plugin in error messages, e.g. "generator 'ours'"; text is "key=value,key=value" or empty.
  ParamSet(std::string owner, const std::string& text);

  int get_int(const std::string& key, int def, int lo, int hi);
  unsigned get_uint(const std::string& key, unsigned def, unsigned lo, unsigned hi);
  float get_float(const std::string& key, float def, float lo, float hi);
  std::string get_choice(const std::string& key, const std::string& def, const std::vector<std::string>& choices);
  // "x/y/z" with each component in [lo, hi].
  Vec3 get_vec3(const std::string& key, Vec3 def, float lo, float hi);
  // "WxH" with both in [lo, hi].
  std::pair<int, int> get_size(const std::string& key, std::pair<int, int> def, int lo, int hi);

  // Throws raycoh::Error for keys given but not asked for.
  void finish() const;
  // "key=value,..." of every parameter asked for, in the order asked, with defaults filled in.
  std::string canonical() const;
  const std::string& owner() const { return owner_; }

 private:
  const std::string* take(const std::string& key);
  template <class Int>
  Int get_integer(const std::string& key, Int def, Int lo, Int hi);
  std::string owner_;
  std::map<std::string, std::string> given_;
  std::vector<std::pair<std::string, std::string>> used_;
};

// "name" or "name:key=val,key=val".
struct PluginSpec {
  std::string name;
  std::string params;  // the text after ':'
  std::string text() const { return params.empty() ? name : name + ":" + params; }
};
PluginSpec parse_plugin_spec(const std::string& text);

// Splits a comma-separated list of plugin specs; an item with '=' and no ':' continues the previous item's
// parameters, so "noopt,ours:tile=8x8,k=16" is {noopt, ours:tile=8x8,k=16}.
std::vector<PluginSpec> split_plugin_list(const std::string& text);

// "1920x1080" -> {1920, 1080}; throws raycoh::Error naming what on a bad value.
std::pair<int, int> parse_size(const std::string& what, const std::string& text, int lo, int hi);

// An integer in [lo, hi]; throws raycoh::Error naming what on a bad value.
int parse_int(const std::string& what, const std::string& text, int lo, int hi);

// Did-you-mean helper for errors: "valid: a, b, c".
std::string join(const std::vector<std::string>& items, const std::string& sep = ", ");

}  // namespace raycoh
