#include "harness/image/device_clock.h"

#include <fmt/format.h>

#include "core/error.h"

namespace raycoh {

void DeviceClock::add(double frame_ms, double error) {
  if (!std::isfinite(frame_ms) || frame_ms < 0)
    throw Error(fmt::format("device clock: frame time {} ms from the CUDA events is not a time", frame_ms));
  last_ms = frame_ms;
  s += frame_ms * 1e-3;
  curve.push_back({s, error});
}

}  // namespace raycoh
