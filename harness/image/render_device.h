// --device cpu|cuda of the rendering commands (`render`, `reference`, `quality`, `converge`): the frames of a render
// on the device path tracer (cuda/device_path_tracer.h) instead of the CPU one, each frame's radiance added to a
// host Accumulator exactly as the CPU path tracer adds its own, so that every figure computed from the images is
// computed the same way. The only file of the commands that sees CUDA (RAYCOH_HAVE_CUDA); builds without CUDA, and
// machines without a device, refuse `cuda` in one line (check_device).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "generators/generator.h"
#include "harness/image/render_common.h"
#include "records/device_stages.h"
#include "shading/image.h"
#include "shading/path_tracer.h"
#include "shading/reference.h"

namespace raycoh {

// The values of --device (and tune's --render-device): the CPU path tracer; the device path tracer with its first
// bounce materialized (the device generator writes the batch, the trace kernel reads it); or with its first bounce
// fused (cuda:pipeline=fused: one kernel per tile makes each ray and traces it from shared memory; every device
// generator, ours and contiguous in tile or group order). Both device forms render the same image bit for bit; rows and
// reference cache entries name which.
inline constexpr const char* kFusedDevice = "cuda:pipeline=fused";
inline bool on_device(const std::string& device) { return device != "cpu"; }
inline bool fused_device(const std::string& device) { return device == kFusedDevice; }

// Throws raycoh::Error naming `option` (--device, tune's --render-device): a value other than cpu, cuda or
// cuda:pipeline=fused, or a device value in a build without CUDA or on a machine without a CUDA device.
void check_device(const std::string& device, const char* option = "--device");

// One frame on the device.
struct DeviceFrame {
  double gpu_ms = 0;     // CUDA events around the frame (cuda/device_path_tracer.h frame_ms)
  DeviceStageMs stages;  // gpu_ms by stage (cuda/device_path_tracer.h DeviceFrameStages)
  uint64_t primary_rays = 0, secondary_rays = 0, bounce_rays = 0, shadow_rays = 0;
  GenerationStats generation;   // the device generator's first-bounce batch
  uint64_t hybrid_diffuse = 0;  // of that batch: rays of a hybrid group with a diffuse class (not in gpu_ms)
  uint64_t rays() const { return primary_rays + secondary_rays + bounce_rays + shadow_rays; }
};

// The frames of one render (one generator, one seed) on the device path tracer; scene and generator outlive it.
class DeviceFrames {
 public:
  // device: cuda or cuda:pipeline=fused (check_device). Throws raycoh::Error in a build without CUDA, without a
  // device, or for a generator without a device version (fused: without a fused form).
  DeviceFrames(const LoadedScene& ls, const Generator& generator, const RenderSettings& rs, const std::string& device);
  ~DeviceFrames();
  DeviceFrames(const DeviceFrames&) = delete;
  DeviceFrames& operator=(const DeviceFrames&) = delete;
  // Frame `frame` added to acc (the settings' size): finite samples added, NaN/Inf counted (Accumulator::add).
  DeviceFrame render(uint32_t frame, Accumulator& acc);
  const std::string& clock() const;   // "measured" on a GPU, "simulated" under GPGPU-Sim
  const std::string& device() const;  // the device's name

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct DeviceRenderTotals {
  double gpu_ms = 0.0;   // sum of the frames' CUDA-event spans (cuda/device_path_tracer.h frame_ms)
  DeviceStageMs stages;  // gpu_ms by stage, summed over the frames
  uint64_t rays = 0;     // every ray traced: camera, first bounce, later bounces, shadow rays
  std::string clock;     // "measured" on a GPU, "simulated" under GPGPU-Sim
  std::string device;    // the device's name
  // Per frame, for the spread across frames: the frame's GPU time (ms) and its first and second bounces' wave trace
  // speeds (MRay/s; NaN where the frame traced no such wave).
  std::vector<double> frame_ms, first_mrays, second_mrays;
};

// The device time of a reference's frames (--device cuda): summed GPU milliseconds, frames, clock and device.
struct DeviceTime {
  double ms = 0;
  int frames = 0;
  std::string clock, device;
};
// --device cuda of a reference: req.make_renderer renders NoOpt's frames on the device path tracer of req.device
// (made when the first frame is needed, so a cached reference never touches the device), each frame's GPU time
// added to *time. ls outlives the request.
void render_reference_on_device(ReferenceRequest& req, const LoadedScene& ls, std::shared_ptr<DeviceTime> time);

// Frames 0 .. frames - 1 with settings rs on `device` into acc; progress(f) after frame f. Throws as DeviceFrames.
DeviceRenderTotals render_on_device(const LoadedScene& ls, const Generator& generator, const RenderSettings& rs,
                                    const std::string& device, int frames, Accumulator& acc,
                                    const std::function<void(int)>& progress);

}  // namespace raycoh
