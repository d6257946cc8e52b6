// Per-stage device times of one frame from CUDA events on the one (default) stream (cuda/stage_clock.cu; plain
// C++ header): the frame is cut into intervals at stage boundaries, each boundary one recorded event (no
// synchronisation), and every interval goes to the stage that was current when it began; wait_ms() waits for
// the last event and sums each stage's intervals. The intervals tile the time from start() to stop(), so the
// stages add up to that span (up to the events' resolution), which lies inside any event pair recorded around
// it. What runs on the stream between two boundaries (kernels, copies, and the device's idle time while the host
// waits or launches) counts for the stage of that interval. Events are made once and reused (grown on demand).
// Throws raycoh::Error on any CUDA error.
#pragma once

#include <memory>

namespace raycoh::cuda {

class StageClock {
 public:
  // stages: how many stages the clock tells apart (stage numbers 0 .. stages - 1).
  explicit StageClock(int stages);
  ~StageClock();
  StageClock(const StageClock&) = delete;
  StageClock& operator=(const StageClock&) = delete;

  // Records the first boundary: time from here counts for `stage`. Forgets the last frame's boundaries.
  void start(int stage);
  // Records a boundary (none when `stage` is already current): time from here counts for `stage`. Returns the
  // stage that was current, so that a nested stage can hand the time back: `int was = enter(t); ...; enter(was)`.
  int enter(int stage);
  // Records the last boundary.
  void stop();
  // Waits for the last boundary; ms[s] = the summed intervals of stage s (size: the clock's stage count).
  void wait_ms(float* ms) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace raycoh::cuda
