#include "harness/common/cli.h"

#include <fmt/format.h>

#include <climits>
#include <string>

#include "core/error.h"

namespace raycoh {

std::string join_specs(const std::vector<PluginSpec>& specs) {
  std::vector<std::string> texts;
  for (const PluginSpec& s : specs) texts.push_back(s.text());
  return join(texts, ",");
}

std::vector<std::string> split_scenes(const std::string& option, const std::string& text) {
  std::vector<std::string> out;
  for (const PluginSpec& s : split_nonempty(option, text)) out.push_back(s.text());
  return out;
}

// A list names each entry once: a repeated entry would write rows with the same key twice.
std::vector<PluginSpec> split_nonempty(const std::string& option, const std::string& text) {
  auto list = split_plugin_list(text);
  if (list.empty()) throw Error(fmt::format("{}: empty list", option));
  for (size_t i = 0; i < list.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (list[i].text() == list[j].text())
        throw Error(fmt::format("{} {}: '{}' is listed twice; name each entry once", option, text, list[i].text()));
  return list;
}

std::pair<int, int> parse_res(const std::string& option, const std::string& text) {
  return parse_size(option, text, 0, INT_MAX);
}

}  // namespace raycoh
