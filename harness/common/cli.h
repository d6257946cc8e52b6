// Option text every command family converts the same way (CLI11 is included here, never in the commands' public
// headers): lists of plugin specs and scenes, and WxH sizes. They only convert text to values; range checks are the
// runners'. The families' own bindings: harness/speed/experiment_cli.h (table, sweep) and
// harness/image/render_cli.h (the rendering commands).
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <utility>
#include <vector>

#include "core/params.h"

namespace raycoh {

std::string join_specs(const std::vector<PluginSpec>& specs);
std::vector<std::string> split_scenes(const std::string& option, const std::string& text);
std::vector<PluginSpec> split_nonempty(const std::string& option, const std::string& text);
// "WxH" without a range (the runner checks it).
std::pair<int, int> parse_res(const std::string& option, const std::string& text);

}  // namespace raycoh
