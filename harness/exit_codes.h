// What main() turns each failure into: one line on stderr and an exit code per kind (README "Exit codes").
// User mistakes stay raycoh::Error (core/error.h, exit 2); the kinds below are not the user's input.
#pragma once

#include <stdexcept>

namespace raycoh {

enum ExitCode : int {
  kExitOk = 0,
  kExitUserError = 2,     // raycoh::Error and command-line parse errors
  kExitDamagedFile = 3,   // a resumed <out>.partial holds a value its column cannot hold
  kExitWriteFailed = 4,   // a CSV could not be written, flushed or renamed (full disk, removed folder)
  kExitOutOfMemory = 5,   // std::bad_alloc
  kExitInternalError = 6  // any other exception: a bug
};

// Not raycoh::Error on purpose: the commands' "rows kept in <out>.partial" wrapping is for user errors only.
struct DamagedFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
struct WriteError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace raycoh
