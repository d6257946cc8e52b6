// `raycoh render --device cuda`: the frames of a render on the device path tracer (cuda/device_path_tracer.h)
// instead of the CPU one, accumulated on the host like the CPU's. Builds without CUDA refuse it.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "generators/generator.h"
#include "harness/image/render_common.h"
#include "shading/image.h"
#include "shading/path_tracer.h"

namespace raycoh {

struct DeviceRenderTotals {
  double gpu_ms = 0.0;  // sum of the frames' CUDA-event spans (cuda/device_path_tracer.h frame_ms)
  uint64_t rays = 0;    // every ray traced: camera, first bounce, later bounces, shadow rays
  std::string clock;    // "measured" on a GPU, "simulated" under GPGPU-Sim
  std::string device;   // the device's name
};

// Frames 0 .. frames - 1 with settings rs into acc; progress(f) after frame f. Throws raycoh::Error in a build
// without CUDA, without a device, or for a generator without a device version.
DeviceRenderTotals render_on_device(const LoadedScene& ls, const Generator& generator, const RenderSettings& rs,
                                    int frames, Accumulator& acc, const std::function<void(int)>& progress);

}  // namespace raycoh
