// A subcommand of the raycoh CLI: one file per command binds its options (CLI11) beside its runner, and main()
// is the list of these bindings. Options are only converted here; the runners check every value (one layer).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/params.h"
#include "records/provenance.h"

namespace CLI {
class App;
}

namespace raycoh {

struct BoundCommand {
  CLI::App* app = nullptr;                    // parsed() tells whether the user chose it
  std::function<int(const Provenance&)> run;  // converts the bound text and runs; returns the exit code
};
using BindCommand = BoundCommand (*)(CLI::App& parent);

BoundCommand bind_list(CLI::App& parent);
BoundCommand bind_scenes_info(CLI::App& parent);
BoundCommand bind_table(CLI::App& parent);
BoundCommand bind_sweep(CLI::App& parent);
BoundCommand bind_rays(CLI::App& parent);
BoundCommand bind_render(CLI::App& parent);
BoundCommand bind_quality(CLI::App& parent);
BoundCommand bind_converge(CLI::App& parent);
BoundCommand bind_compare(CLI::App& parent);
BoundCommand bind_validate(CLI::App& parent);
BoundCommand bind_merge(CLI::App& parent);
BoundCommand bind_stability(CLI::App& parent);
BoundCommand bind_report(CLI::App& parent);
BoundCommand bind_reference(CLI::App& parent);
BoundCommand bind_reference_combine(CLI::App& parent);
BoundCommand bind_tune(CLI::App& parent);

}  // namespace raycoh
