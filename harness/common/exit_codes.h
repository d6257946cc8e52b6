// What main() turns each failure into: one line on stderr and an exit code (README "Exit codes"). Only 0, 1 and 2
// are ever returned, and 3 by `raycoh stability` alone (a measured rate above its threshold); a signal ends the process
// with 128 + its number (Ctrl-C 130, SIGTERM 143, a failed invariant check's abort 134).
#pragma once

#include "core/durable_file.h"  // WriteError
#include "core/error.h"         // Error

namespace raycoh {

enum ExitCode : int {
  kExitOk = 0,
  kExitFailure = 1,            // not the user's input: a write the system refused (WriteError), a device fault, out of
                               // memory, a bug
  kExitUserError = 2,          // the user's input: raycoh::Error (names, values, files, a resume file of another run)
  kExitThresholdExceeded = 3,  // `raycoh stability`: the run finished, and a rate exceeds its threshold
};

}  // namespace raycoh
