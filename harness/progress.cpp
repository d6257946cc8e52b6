#include "harness/progress.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>

namespace raycoh {

Progress::Progress() : start_(std::chrono::steady_clock::now()) {
  enabled_ = ::isatty(STDERR_FILENO) != 0 && std::getenv("CI") == nullptr;
}

void Progress::update(size_t item, size_t items, int step, int steps, const std::string& label) {
  if (!enabled_ || items == 0 || steps <= 0) return;
  const double done = (static_cast<double>(item) + static_cast<double>(step) / steps) / static_cast<double>(items);
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const int width = 30, filled = static_cast<int>(done * width);
  std::string bar(static_cast<size_t>(filled), '#');
  bar.resize(width, '.');
  char eta[32] = "";
  if (done > 0.02) std::snprintf(eta, sizeof eta, ", ~%.0f s left", elapsed / done - elapsed);
  std::fprintf(stderr, "\r[%s] %3.0f%% %s %zu/%zu frame %d/%d%s\033[K", bar.c_str(), 100 * done, label.c_str(),
               item + 1, items, step + 1, steps, eta);
  shown_ = true;
}

void Progress::clear() {
  if (shown_) std::fprintf(stderr, "\r\033[K");
  shown_ = false;
}

}  // namespace raycoh
