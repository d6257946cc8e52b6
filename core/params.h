// Checked parameter sets for plugins ("ours:tile=8x8,k=8", "voxels:size=96", "embree:mode=packet16").
//
// Each plugin declares its parameters once, as a ParamTable next to its factory (name, type, default, range or
// choices, one line of doc), and reads every value through it: the table is what `raycoh list` prints, so the
// listed default and range are the ones that run. finish() then rejects any key that was given but never asked
// for, naming the valid keys. canonical() is the full, defaulted set that ran, which every result row records.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/vec.h"

namespace raycoh {

enum class ParamType { Int, Uint, Float, Choice, Size };

// One parameter of a plugin.
struct ParamSpec {
  std::string name;
  ParamType type = ParamType::Int;
  std::string def;                   // the default as canonical() writes it ("8x8", "0.25", "tile")
  double lo = 0, hi = 0;             // Int, Uint, Float: the range; Size: the range of each side
  std::vector<std::string> choices;  // Choice
  std::string doc;                   // one line for `raycoh list`
};
using ParamTable = std::vector<ParamSpec>;

// Table rows with a typed default (written once, formatted as canonical() writes it).
ParamSpec int_param(std::string name, int def, int lo, int hi, std::string doc);
ParamSpec uint_param(std::string name, unsigned def, unsigned lo, unsigned hi, std::string doc);
ParamSpec float_param(std::string name, float def, float lo, float hi, std::string doc);
ParamSpec choice_param(std::string name, std::string def, std::vector<std::string> choices, std::string doc);
ParamSpec size_param(std::string name, std::pair<int, int> def, int lo, int hi, std::string doc);

// "name  type  default  range  doc" per row, aligned, each line starting with indent; "(no parameters)" if empty.
std::string format_param_table(const ParamTable& table, const std::string& indent);
// "name=default" pairs of the table in order: the canonical set a plugin reads with no parameters given.
std::string default_params(const ParamTable& table);
// One line: "name=default (range), ..." or "(no parameters)".
std::string param_summary(const ParamTable& table);

class ParamSet {
 public:
  ParamSet() = default;
  // owner names the plugin in error messages, e.g. "generator 'ours'"; text is "key=value,key=value" or empty.
  ParamSet(std::string owner, const std::string& text);
  // The same, for a plugin that reads its values through table (which must outlive the set).
  ParamSet(std::string owner, const std::string& text, const ParamTable& table);

  // Reads key through the table row of that name, with its default and range or choices.
  int get_int(const std::string& key);
  unsigned get_uint(const std::string& key);
  float get_float(const std::string& key);
  std::string get_choice(const std::string& key);
  std::pair<int, int> get_size(const std::string& key);
  // An Int row whose upper end depends on another parameter (k <= W H): [lo, min(hi, at_most)].
  int get_int_at_most(const std::string& key, int at_most);

  // Reads key with the default and range given here: for readers without a table (file scenes' sun, the simt
  // tracer until it declares one, the GPU keys' re-read of an encoder's canonical set).
  int get_int(const std::string& key, int def, int lo, int hi);
  unsigned get_uint(const std::string& key, unsigned def, unsigned lo, unsigned hi);
  float get_float(const std::string& key, float def, float lo, float hi);
  std::string get_choice(const std::string& key, const std::string& def, const std::vector<std::string>& choices);
  // "x/y/z" with each component in [lo, hi].
  Vec3 get_vec3(const std::string& key, Vec3 def, float lo, float hi);
  // "WxH" with both in [lo, hi].
  std::pair<int, int> get_size(const std::string& key, std::pair<int, int> def, int lo, int hi);

  // Throws raycoh::Error for keys given but not asked for (and for table rows the plugin never read).
  void finish() const;
  // "key=value,..." of every parameter asked for, in the order asked, with defaults filled in.
  std::string canonical() const;
  const std::string& owner() const { return owner_; }

 private:
  const std::string* take(const std::string& key);
  const ParamSpec& row(const std::string& key, ParamType type) const;
  template <class Int>
  Int get_integer(const std::string& key, Int def, Int lo, Int hi);
  std::string owner_;
  const ParamTable* table_ = nullptr;
  std::map<std::string, std::string> given_;
  std::vector<std::pair<std::string, std::string>> used_;
  void use(const std::string& key, std::string value);
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
