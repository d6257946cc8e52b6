// Output files that are whole or absent, locks on output paths, and what Ctrl-C leaves behind (host only, POSIX).
//
// Every result file raycoh writes goes through here: a write the disk refuses (full disk, a file size limit, a
// removed folder) is a WriteError naming the file and the reason, never a short file that looks complete. A
// finished file is fsynced, renamed into place and its folder fsynced before a command says "Wrote".
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace raycoh {

// A write the system refused: not the user's input (main: "error: write failed", exit 1).
struct WriteError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Writes all of `data` to `fd` (retrying short writes and EINTR); throws WriteError "<what>: <reason>".
void write_all(int fd, std::string_view data, const std::string& what);
// fsync of an open file; throws WriteError.
void sync_file(int fd, const std::string& what);
// fsync of the folder holding `path`, so that a rename into it survives a crash (errors other than EINVAL, a
// file system without folder sync, throw WriteError).
void sync_parent_folder(const std::string& path);

// ".<name>.tmp<pid><ext>" beside `path` (the extension kept last: image writers choose the format by it).
std::string temp_path_beside(const std::string& path);

// Writes `bytes` to `path` whole or not at all: a temp file beside it, written, fsynced and closed with every
// call checked, renamed over `path`, then the folder fsynced. On failure the temp file is removed and WriteError
// names `path` and the reason; an existing `path` is left as it was.
void write_file_atomically(const std::string& path, std::string_view bytes);
// The same for a file written in pieces: `write` gets the temp file's descriptor and writes it with write_all; the
// file is synced and moved into place only when `write` returns. A throw removes the temp file and propagates.
void write_file_atomically(const std::string& path, const std::function<void(int fd)>& write);

// Moves a finished temp file over `path` (rename, then folder fsync); removes `tmp` and throws WriteError on
// failure.
void commit_temp_file(const std::string& tmp, const std::string& path);

// `option path` must name a file that can be created: not a folder, in a folder that exists or can be created
// and is writable. Throws raycoh::Error (the user's input, exit 2) naming the option. Creates missing folders.
void check_output_file(const std::string& option, const std::string& path);
// `option dir` must be a folder that exists or can be created, and is writable. Throws raycoh::Error.
void check_output_folder(const std::string& option, const std::string& dir);

// An exclusive lock on an output (a CSV being written, a cache entry being rendered), held from construction
// to destruction: the lock file "<target>.lock" names its holder (pid, host, start time, command line) and is
// removed when the lock is released. A run killed outright releases the lock with its process (flock); its
// stale lock file is taken over by the next run.
class OutputLock {
 public:
  enum class Wait { No, Yes };
  OutputLock() = default;
  // Wait::No: throws raycoh::Error naming `what` and the holder when another run holds the lock (exit 2).
  // Wait::Yes: prints whom it waits for on stderr and blocks until the holder is done.
  OutputLock(const std::string& target, const std::string& what, Wait wait = Wait::No);
  OutputLock(OutputLock&& other) noexcept;
  OutputLock& operator=(OutputLock&& other) noexcept;
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;
  ~OutputLock();
  void release();
  bool held() const { return fd_ >= 0; }

 private:
  int fd_ = -1;
  int slot_ = -1;  // interrupt cleanup slot of the lock file
  std::string path_;
};

// Ctrl-C (SIGINT) and SIGTERM: print "raycoh: interrupted" with the hint of the run in progress (how to resume),
// remove registered lock and temp files, then die of the signal (exit status 128 + signal). SIGXFSZ is ignored,
// so that a file size limit is a failed write (WriteError), not a silent kill. A SIGINT that was ignored when the
// process started (a background job) stays ignored. Called once by main().
void install_signal_handlers();
// The line printed after "raycoh: interrupted: " while a run writes its rows; empty clears it.
void set_interrupt_hint(const std::string& hint);
// Paths removed if the process is interrupted (temp files, lock files); returns a slot for unregister.
int register_interrupt_cleanup(const std::string& path);
void unregister_interrupt_cleanup(int slot);

}  // namespace raycoh
