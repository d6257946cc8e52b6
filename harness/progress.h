// A one-line progress bar on stderr, shown only when stderr is a terminal (quiet in CI logs and pipes).
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
  bool enabled_ = false;
  bool shown_ = false;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace raycoh
