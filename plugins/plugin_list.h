// The text of `raycoh list`, generated from the registries' records (core/plugin.h): every generator, encoder,
// tracer and built-in scene with its summary and parameter table (name, type, default, range, doc).
#pragma once

#include <string>

namespace raycoh {

std::string plugin_list_text();

}  // namespace raycoh
