// Progress with a time estimate on stderr. On a terminal: a one-line bar redrawn in place. Otherwise (a log file,
// a pipe, CI): a plain line per step, at most one every RAYCOH_PROGRESS_SECONDS (default 10) seconds, so a run
// shorter than that prints none.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace raycoh {

class Progress {
 public:
  Progress();
  // Work item `item` of `items` (e.g. scene), step `step` of `steps` inside it (e.g. frame).
  void update(size_t item, size_t items, int step, int steps, const std::string& label);
  void clear();
  bool enabled() const { return enabled_; }

 private:
  bool enabled_ = false;  // stderr is a terminal: the bar
  bool shown_ = false;
  double log_every_s_ = 10;
  std::chrono::steady_clock::time_point start_, last_line_;
};

}  // namespace raycoh
