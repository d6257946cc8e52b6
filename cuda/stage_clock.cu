// Stage boundaries as CUDA events (cuda/stage_clock.h).
#include <cuda_runtime.h>

#include <string>
#include <vector>

#include "core/error.h"
#include "cuda/cuda_check.cuh"
#include "cuda/stage_clock.h"

namespace raycoh::cuda {

struct StageClock::Impl {
  int stages = 0;
  std::vector<cudaEvent_t> events;  // the pool; events[0, used) are this frame's boundaries
  std::vector<int> stage_of;        // stage_of[i]: the stage of the interval that starts at boundary i
  size_t used = 0;
  int current = -1;  // -1: not started, or stopped

  void record(int stage) {
    if (used == events.size()) {
      cudaEvent_t e = nullptr;
      RAYCOH_CUDA_CHECK(cudaEventCreate(&e));
      events.push_back(e);
      stage_of.push_back(0);
    }
    RAYCOH_CUDA_CHECK(cudaEventRecord(events[used]));
    stage_of[used] = stage;
    ++used;
    current = stage;
  }

  void check(int stage) const {
    if (stage < 0 || stage >= stages) throw Error("cuda: stage clock: no stage " + std::to_string(stage));
  }
};

StageClock::StageClock(int stages) : impl_(std::make_unique<Impl>()) {
  if (stages < 1) throw Error("cuda: stage clock: at least one stage");
  impl_->stages = stages;
}

StageClock::~StageClock() {
  for (cudaEvent_t e : impl_->events) report_cuda(cudaEventDestroy(e), "cudaEventDestroy");
}

void StageClock::start(int stage) {
  impl_->check(stage);
  impl_->used = 0;
  impl_->record(stage);
}

int StageClock::enter(int stage) {
  Impl& m = *impl_;
  m.check(stage);
  const int was = m.current;
  if (was < 0) throw Error("cuda: stage clock: enter before start");
  if (stage != was) m.record(stage);
  return was;
}

void StageClock::stop() {
  Impl& m = *impl_;
  if (m.current < 0) throw Error("cuda: stage clock: stop before start");
  m.record(m.current);
  m.current = -1;
}

void StageClock::wait_ms(float* ms) const {
  const Impl& m = *impl_;
  if (m.current >= 0 || m.used < 2) throw Error("cuda: stage clock: read before stop");
  for (int s = 0; s < m.stages; ++s) ms[s] = 0.f;
  wait_event(m.events[m.used - 1]);
  for (size_t i = 0; i + 1 < m.used; ++i) {
    float interval = 0.f;
    RAYCOH_CUDA_CHECK(cudaEventElapsedTime(&interval, m.events[i], m.events[i + 1]));
    ms[m.stage_of[i]] += interval;
  }
}

}  // namespace raycoh::cuda
