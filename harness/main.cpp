// raycoh command line: a list of commands (harness/common/command.h), each bound in its own file. Every failure ends in
// one line on stderr and an exit code of harness/common/exit_codes.h (user errors: 2, other failures: 1).
#include <tbb/global_control.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <new>
#include <string>
#include <thread>

#include "core/error.h"
#include "harness/common/command.h"
#include "harness/common/exit_codes.h"

namespace {

using namespace raycoh;

// In the order `raycoh --help` lists them.
const BindCommand kCommands[] = {bind_list,    bind_scenes_info, bind_table,
                                 bind_sweep,   bind_merge,       bind_validate,
                                 bind_render,  bind_reference,   bind_reference_combine,
                                 bind_quality, bind_converge,    bind_compare,
                                 bind_rays,    bind_report,      bind_stability,
                                 bind_tune};

int fail(int code, const char* kind, const std::string& message) {
  std::fprintf(stderr, "raycoh: %s: %s\n", kind, one_line(message).c_str());
  return code;
}

// Runs the chosen command; any exception becomes one line and its exit code.
template <class Fn>
int run_reporting_failures(Fn&& run) {
  try {
    return run();
  } catch (const DeviceFault& e) {
    return fail(kExitFailure, "device fault", e.what());
  } catch (const Error& e) {
    return fail(kExitUserError, "error", e.what());
  } catch (const WriteError& e) {
    return fail(kExitFailure, "error: write failed", e.what());
  } catch (const std::bad_alloc&) {
    return fail(kExitFailure, "error",
                "out of memory (rows measured so far stay in the .partial file beside --out; a smaller --res "
                "needs less)");
  } catch (const std::exception& e) {
    return fail(kExitFailure, "internal error", e.what());
  } catch (...) {
    return fail(kExitFailure, "internal error", "unknown exception");
  }
}

// The first word that is not an option must be a command (CLI11 would take it for an extra argument).
bool check_command_word(const CLI::App& app, int argc, char** argv) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands({})) names.push_back(sub->get_name());
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.rfind("-", 0) == 0) {
      if (arg == "--threads") ++i;
      continue;
    }
    if (std::find(names.begin(), names.end(), arg) != names.end()) return true;
    std::fprintf(stderr, "raycoh: error: unknown command '%s'; valid commands: %s\n", arg.c_str(), join(names).c_str());
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  install_signal_handlers();
  CLI::App app{"raycoh: which way of making secondary rays coherent pays off, on which scene, at what cost"};
  app.require_subcommand(1);
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  app.add_option("--threads", threads, "worker threads (default: all cores)")->check(CLI::Range(1, 1024));
  std::vector<BoundCommand> commands;
  for (BindCommand bind : kCommands) commands.push_back(bind(app));

  if (!check_command_word(app, argc, argv)) return kExitUserError;
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "raycoh: error: %s (see raycoh --help)\n", e.what());
    return kExitUserError;
  }

  tbb::global_control threads_control(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
  const Provenance provenance = collect_provenance(argc, argv, threads);
  return run_reporting_failures([&] {
    for (const BoundCommand& c : commands)
      if (c.app->parsed()) return c.run(provenance);
    return static_cast<int>(kExitOk);
  });
}
