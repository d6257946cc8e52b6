// `raycoh list`: every plugin with its parameters (type, default, range), rendered from the registries.
#include <CLI/CLI.hpp>
#include <cstdio>

#include "harness/common/command.h"
#include "plugins/plugin_list.h"

namespace raycoh {

BoundCommand bind_list(CLI::App& parent) {
  CLI::App* cmd =
      parent.add_subcommand("list", "list generators, encoders, tracers and built-in scenes with their parameters");
  return {cmd, [](const Provenance&) {
            std::fputs(plugin_list_text().c_str(), stdout);
            return 0;
          }};
}

}  // namespace raycoh
