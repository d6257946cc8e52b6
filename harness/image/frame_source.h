// The frames of one render (one generator, one seed) on the path tracer --device names: the CPU's
// (shading/path_tracer.h, every batch traced by --tracer) or the device's (harness/image/render_device.h). Either adds
// each frame to the caller's Accumulator the same way, so `quality` and `converge` compute every figure from the
// images alike whichever device rendered them.
//
// On the device, a frame's FrameStats hold its wall time (the call, GPU and host together), its ray counts and the
// device generator's statistics; trace_s and gen_s are 0 (not measured apart: the device's clock is gpu_ms, CUDA
// events around the frame, labelled by clock()); hybrid_diffuse is counted on the device after the frame's span.
// The denoiser's first-hit albedo and normal (aux) come from a CPU camera pass of the same frame and seed,
// whose camera rays are the device's bit for bit.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "generators/generator.h"
#include "harness/image/render_common.h"
#include "records/device_stages.h"
#include "shading/image.h"
#include "shading/path_tracer.h"

namespace raycoh {

class DeviceFrames;

struct SourcedFrame {
  FrameStats stats;
  double gpu_ms = std::nan("");  // the device's time of the frame (CUDA events); NaN on the CPU
  DeviceStageMs gpu_stages;      // gpu_ms by stage; NaN on the CPU
};

class FrameSource {
 public:
  // device: a --device value (cpu, cuda, cuda:pipeline=fused; check_device has accepted it). ls and generator outlive
  // the source.
  FrameSource(const std::string& device, const LoadedScene& ls, Generator& generator, const RenderSettings& rs);
  ~FrameSource();
  FrameSource(const FrameSource&) = delete;
  FrameSource& operator=(const FrameSource&) = delete;
  // Frame `frame` added to acc; with aux, also its first hits' albedo and normal.
  SourcedFrame render(uint32_t frame, Accumulator& acc, AuxAccumulators* aux = nullptr);
  bool on_device() const { return device_ != nullptr; }
  // "measured" | "simulated" on the device, "" on the CPU.
  std::string clock() const;
  // The device's name on the device, "cpu" on the CPU.
  std::string device_name() const;

 private:
  std::unique_ptr<PathTracer> cpu_;  // the CPU path tracer (--device cpu), or the aux pass's (--device cuda)
  std::unique_ptr<DeviceFrames> device_;
};

}  // namespace raycoh
