#include "harness/common/progress.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>

namespace raycoh {

Progress::Progress() : start_(std::chrono::steady_clock::now()), last_line_(start_) {
  enabled_ = ::isatty(STDERR_FILENO) != 0 && std::getenv("CI") == nullptr;
  if (const char* every = std::getenv("RAYCOH_PROGRESS_SECONDS")) log_every_s_ = std::atof(every);
}

void Progress::update(size_t item, size_t items, int step, int steps, const std::string& label) {
  if (items == 0 || steps <= 0) return;
  const double done = (static_cast<double>(item) + static_cast<double>(step) / steps) / static_cast<double>(items);
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (!enabled_) {  // a log: one plain line per step, throttled
    if (std::chrono::duration<double>(now - last_line_).count() < log_every_s_) return;
    last_line_ = now;
    std::fprintf(stderr, "progress: %3.0f%% %s (%zu/%zu, step %d/%d), %.0f s elapsed", 100 * done, label.c_str(),
                 item + 1, items, step + 1, steps, elapsed);
    if (done > 0.02) std::fprintf(stderr, ", ~%.0f s left", elapsed / done - elapsed);
    std::fprintf(stderr, "\n");
    return;
  }
  const int width = 30, filled = static_cast<int>(done * width);
  std::string bar(static_cast<size_t>(filled), '#');
  bar.resize(width, '.');
  char eta[32] = "";
  if (done > 0.02) std::snprintf(eta, sizeof eta, ", ~%.0f s left", elapsed / done - elapsed);
  std::fprintf(stderr, "\r[%s] %3.0f%% %s (%zu/%zu, step %d/%d)%s\033[K", bar.c_str(), 100 * done, label.c_str(),
               item + 1, items, step + 1, steps, eta);
  shown_ = true;
}

void Progress::clear() {
  if (shown_) std::fprintf(stderr, "\r\033[K");
  shown_ = false;
}

}  // namespace raycoh
