#include "core/durable_file.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>

#include "core/error.h"

namespace raycoh {

namespace fs = std::filesystem;

namespace {

std::string reason(int err) { return std::strerror(err); }

// What SIGINT/SIGTERM print and remove: fixed buffers, read by the handler without allocating.
constexpr int kSlots = 32;
constexpr size_t kPathMax = 4096;
char g_hint[kPathMax];
char g_paths[kSlots][kPathMax];
std::atomic<bool> g_used[kSlots];

void copy_bounded(char* dst, const std::string& src) {
  const size_t n = std::min(src.size(), kPathMax - 1);
  std::memcpy(dst, src.data(), n);
  dst[n] = '\0';
}

void put_stderr(const char* s) {
  size_t n = std::strlen(s);
  while (n > 0) {
    const ssize_t w = ::write(STDERR_FILENO, s, n);
    if (w <= 0) return;
    s += w;
    n -= static_cast<size_t>(w);
  }
}

std::atomic<bool> g_terminating{false};

extern "C" void on_terminating_signal(int sig) {
  // `timeout` signals the process and then its process group: a second thread may take the second signal while the
  // first cleans up. Only the first says so and removes the files; it then re-raises, which ends the process.
  if (g_terminating.exchange(true)) return;
  put_stderr(sig == SIGINT ? "\nraycoh: interrupted" : "\nraycoh: terminated");
  if (g_hint[0] != '\0') {
    put_stderr(": ");
    put_stderr(g_hint);
  }
  put_stderr("\n");
  for (int i = 0; i < kSlots; ++i)
    if (g_used[i].load()) ::unlink(g_paths[i]);
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

std::string read_holder(const std::string& lock_path) {
  std::ifstream in(lock_path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  return text.empty() ? std::string("a raycoh run that has not said who it is yet") : text;
}

std::string self_description() {
  std::string cmd;
  {
    std::ifstream in("/proc/self/cmdline", std::ios::binary);
    std::string arg;
    while (std::getline(in, arg, '\0')) cmd += (cmd.empty() ? "" : " ") + arg;
  }
  char host[256] = "unknown-host";
  ::gethostname(host, sizeof host - 1);
  char when[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  return fmt::format("pid {} on {} since {}: {}", ::getpid(), host, when, cmd);
}

}  // namespace

void write_all(int fd, std::string_view data, const std::string& what) {
  while (!data.empty()) {
    const ssize_t w = ::write(fd, data.data(), data.size());
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) throw WriteError(fmt::format("{}: {}", what, reason(w < 0 ? errno : ENOSPC)));
    data.remove_prefix(static_cast<size_t>(w));
  }
}

void sync_file(int fd, const std::string& what) {
  if (::fsync(fd) != 0 && errno != EINVAL) throw WriteError(fmt::format("{}: sync failed: {}", what, reason(errno)));
}

void sync_parent_folder(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  const std::string dir = parent.empty() ? "." : parent.string();
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) throw WriteError(fmt::format("{}: cannot open its folder to sync it: {}", path, reason(errno)));
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0 && err != EINVAL) throw WriteError(fmt::format("{}: folder sync failed: {}", path, reason(err)));
}

std::string temp_path_beside(const std::string& path) {
  const fs::path p(path);
  std::string name = p.stem().string();
  name.insert(name.begin(), '.');  // not "." + string: GCC 12 warns falsely on that (PR 105329)
  name += ".tmp" + std::to_string(::getpid()) + p.extension().string();
  return (p.parent_path() / name).string();
}

void commit_temp_file(const std::string& tmp, const std::string& path) {
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw WriteError(fmt::format("{}: cannot move the finished file into place: {}", path, ec.message()));
  }
  sync_parent_folder(path);
}

void write_file_atomically(const std::string& path, std::string_view bytes) {
  write_file_atomically(path, [&](int fd) { write_all(fd, bytes, path); });
}

void write_file_atomically(const std::string& path, const std::function<void(int fd)>& write) {
  const std::string tmp = temp_path_beside(path);
  const int slot = register_interrupt_cleanup(tmp);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    unregister_interrupt_cleanup(slot);
    throw WriteError(fmt::format("{}: cannot create {}: {}", path, tmp, reason(errno)));
  }
  try {
    write(fd);
    sync_file(fd, path);
  } catch (...) {
    ::close(fd);
    ::unlink(tmp.c_str());
    unregister_interrupt_cleanup(slot);
    throw;
  }
  if (::close(fd) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    unregister_interrupt_cleanup(slot);
    throw WriteError(fmt::format("{}: closing failed: {}", path, reason(err)));
  }
  unregister_interrupt_cleanup(slot);
  commit_temp_file(tmp, path);
}

void check_output_folder(const std::string& option, const std::string& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw Error(fmt::format("{} {}: is a file, not a folder", option, dir));
  fs::create_directories(dir, ec);
  if (ec) throw Error(fmt::format("{} {}: cannot create the folder: {}", option, dir, ec.message()));
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw Error(fmt::format("{} {}: the folder is not writable ({})", option, dir, reason(errno)));
}

void check_output_file(const std::string& option, const std::string& path) {
  if (path.empty()) throw Error(fmt::format("{}: empty path", option));
  std::error_code ec;
  if (fs::is_directory(path, ec))
    throw Error(fmt::format("{} {}: is a folder; name a file in it (e.g. {}/out.csv)", option, path,
                            fs::path(path).lexically_normal().string()));
  const fs::path parent = fs::path(path).parent_path();
  check_output_folder(option + " " + path + ": folder", parent.empty() ? "." : parent.string());
  if (fs::exists(path, ec) && ::access(path.c_str(), W_OK) != 0)
    throw Error(fmt::format("{} {}: the file is not writable ({})", option, path, reason(errno)));
}

OutputLock::OutputLock(const std::string& target, const std::string& what, Wait wait) : path_(target + ".lock") {
  for (;;) {
    const int fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) throw Error(fmt::format("{}: cannot create the lock file {}: {}", what, path_, reason(errno)));
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      if (err != EWOULDBLOCK) {
        ::close(fd);
        throw Error(fmt::format("{}: cannot lock {}: {}", what, path_, reason(err)));
      }
      const std::string holder = read_holder(path_);
      if (wait == Wait::No) {
        ::close(fd);
        throw Error(
            fmt::format("{} is being written by another run ({}); wait for it to finish or choose another "
                        "output (lock file {})",
                        what, holder, path_));
      }
      std::fprintf(stderr, "%s: waiting for %s\n", what.c_str(), holder.c_str());
      while (::flock(fd, LOCK_EX) != 0)
        if (errno != EINTR) throw Error(fmt::format("{}: cannot lock {}: {}", what, path_, reason(errno)));
    }
    // The holder before us may have removed the file while we waited: the lock must be on the file at the path.
    struct stat held {
    }, now{};
    if (::fstat(fd, &held) == 0 && ::stat(path_.c_str(), &now) == 0 && held.st_ino == now.st_ino &&
        held.st_dev == now.st_dev) {
      fd_ = fd;
      break;
    }
    ::close(fd);
  }
  const std::string me = self_description() + "\n";
  if (::ftruncate(fd_, 0) == 0) {
    try {
      write_all(fd_, me, path_);
    } catch (const WriteError&) {
      // Who holds the lock is a courtesy for the next run's message; the lock itself is held.
    }
  }
  slot_ = register_interrupt_cleanup(path_);
}

OutputLock::OutputLock(OutputLock&& o) noexcept : fd_(o.fd_), slot_(o.slot_), path_(std::move(o.path_)) {
  o.fd_ = -1;
  o.slot_ = -1;
}

OutputLock& OutputLock::operator=(OutputLock&& o) noexcept {
  if (this != &o) {
    release();
    fd_ = o.fd_;
    slot_ = o.slot_;
    path_ = std::move(o.path_);
    o.fd_ = -1;
    o.slot_ = -1;
  }
  return *this;
}

OutputLock::~OutputLock() { release(); }

void OutputLock::release() {
  if (fd_ < 0) return;
  ::unlink(path_.c_str());  // while still held: a waiter re-checks that its lock is on the file at the path
  ::close(fd_);
  fd_ = -1;
  unregister_interrupt_cleanup(slot_);
  slot_ = -1;
}

void install_signal_handlers() {
  // A SIGINT ignored from the start (a background job of a non-interactive shell, which must not die of the
  // terminal's Ctrl-C) stays ignored.
  if (std::signal(SIGINT, on_terminating_signal) == SIG_IGN) std::signal(SIGINT, SIG_IGN);
  std::signal(SIGTERM, on_terminating_signal);
  std::signal(SIGXFSZ, SIG_IGN);
}

void set_interrupt_hint(const std::string& hint) {
  g_hint[0] = '\0';
  if (!hint.empty()) copy_bounded(g_hint, hint);
}

int register_interrupt_cleanup(const std::string& path) {
  for (int i = 0; i < kSlots; ++i) {
    if (g_used[i].load()) continue;
    copy_bounded(g_paths[i], path);
    g_used[i].store(true);
    return i;
  }
  return -1;  // all slots taken: the file stays behind if interrupted, nothing worse
}

void unregister_interrupt_cleanup(int slot) {
  if (slot >= 0 && slot < kSlots) g_used[slot].store(false);
}

}  // namespace raycoh
