// The device's clock of `converge --device cuda`: per generator, the sum of its frames' GPU times from the device path
// tracer's CUDA events (cuda/device_path_tracer.h frame_ms), and its error curve against that sum. Labelled by the
// device: "measured" on a GPU, "simulated" under GPGPU-Sim; its own columns (frame_gpu_ms, gpu_s) and its own
// summary rows (clock measured_gpu or simulated_gpu), never added to the wall, trace or modeled clocks.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "records/curves.h"

namespace raycoh {

struct DeviceClock {
  std::string label;              // "measured" | "simulated"; empty: no device clock (--device cpu)
  double s = 0;                   // GPU seconds of the frames so far
  double last_ms = std::nan("");  // the last frame's GPU milliseconds
  std::vector<CurvePoint> curve;  // error against s, one point per frame
  bool active() const { return !label.empty(); }
  // The summary's clock name: "measured_gpu" or "simulated_gpu".
  std::string clock_name() const { return label + "_gpu"; }
  // One more frame of frame_ms GPU milliseconds after which the running mean's error is `error`. Throws
  // raycoh::Error when frame_ms is not finite and >= 0 (a device time that cannot be one).
  void add(double frame_ms, double error);
};

}  // namespace raycoh
