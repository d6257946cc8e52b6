// --device cuda of the rendering commands (render_device.h).
#include "harness/image/render_device.h"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <vector>

#include "core/error.h"
#include "shading/emitters.h"
#if defined(RAYCOH_HAVE_CUDA)
#include "cuda/cuda_device.h"
#include "cuda/device_path_tracer.h"
#endif

namespace raycoh {

namespace {

[[maybe_unused]] constexpr const char* kNoCuda =
    "{} {}: this build has no CUDA (configure with nvcc found, RAYCOH_CUDA=ON)";
[[maybe_unused]] constexpr const char* kNoDevice = "{} {}: no CUDA device (this machine has no usable GPU)";

}  // namespace

void check_device(const std::string& device, const char* option) {
  if (device == "cpu") return;
  if (device != "cuda" && !fused_device(device))
    throw Error(
        fmt::format("{} {}: expected cpu, cuda or {} (the device path tracer, its first bounce materialized or fused)",
                    option, device, kFusedDevice));
#if defined(RAYCOH_HAVE_CUDA)
  if (cuda::device_count() == 0) throw Error(fmt::format(fmt::runtime(kNoDevice), option, device));
#else
  throw Error(fmt::format(fmt::runtime(kNoCuda), option, device));
#endif
}

#if defined(RAYCOH_HAVE_CUDA)

struct DeviceFrames::Impl {
  std::string device, clock;
  EmitterDistribution lights;
  cuda::DevicePathTracer tracer;
  std::vector<Vec3> radiance;
  Impl(const LoadedScene& ls, const Generator& g, const RenderSettings& rs, bool fused)
      : lights(ls.scene),
        tracer(ls.scene, ls.bvh, lights.view(ls.scene), g,
               cuda::DevicePathSettings{rs.width, rs.height, rs.seed, rs.max_depth, rs.rr_depth, fused}) {}
};

DeviceFrames::DeviceFrames(const LoadedScene& ls, const Generator& generator, const RenderSettings& rs,
                           const std::string& device) {
  check_device(device);
  impl_ = std::make_unique<Impl>(ls, generator, rs, fused_device(device));
  impl_->device = cuda::device_name();
  std::string lower = impl_->device;
  for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  const bool sim = lower.find("gpgpu") != std::string::npos || lower.starts_with("simulated");
  impl_->clock = sim ? "simulated" : "measured";
}

DeviceFrame DeviceFrames::render(uint32_t frame, Accumulator& acc) {
  const cuda::DeviceFrameStats s = impl_->tracer.render_frame(frame, impl_->radiance);
  RAYCOH_CHECK(impl_->radiance.size() == static_cast<size_t>(acc.width()) * static_cast<size_t>(acc.height()),
               "device frame of another size than the accumulator");
  for (size_t p = 0; p < impl_->radiance.size(); ++p) acc.add(p, impl_->radiance[p]);
  DeviceFrame f;
  f.gpu_ms = s.frame_ms;
  f.stages = {s.stages.camera_ms,
              s.stages.generation_ms,
              s.stages.next_event_ms,
              s.stages.sample_ms,
              s.stages.trace_ms,
              s.stages.gather_ms,
              s.stages.first_wave_trace_ms,
              s.stages.second_wave_trace_ms,
              static_cast<double>(s.rays.secondary),
              static_cast<double>(s.rays.second)};
  f.primary_rays = s.rays.primary;
  f.secondary_rays = s.rays.secondary;
  f.bounce_rays = s.rays.bounce;
  f.shadow_rays = s.rays.shadow;
  f.generation = s.generation;
  f.hybrid_diffuse = s.hybrid_diffuse;
  return f;
}

#else

struct DeviceFrames::Impl {
  std::string device, clock;
};

DeviceFrames::DeviceFrames(const LoadedScene&, const Generator&, const RenderSettings&, const std::string& device) {
  check_device(device);
  throw Error(fmt::format(fmt::runtime(kNoCuda), "--device", device));
}

DeviceFrame DeviceFrames::render(uint32_t, Accumulator&) {
  throw Error(fmt::format(fmt::runtime(kNoCuda), "--device", "cuda"));
}

#endif

DeviceFrames::~DeviceFrames() = default;
const std::string& DeviceFrames::clock() const { return impl_->clock; }
const std::string& DeviceFrames::device() const { return impl_->device; }

void render_reference_on_device(ReferenceRequest& req, const LoadedScene& ls, std::shared_ptr<DeviceTime> time) {
  const RenderSettings rs = req.settings;
  const std::string device = req.device;
  req.make_renderer = [&ls, rs, device, time]() -> FrameRenderer {
    struct Frames {
      std::unique_ptr<Generator> noopt = make_generator({"noopt", ""});
      std::unique_ptr<DeviceFrames> frames;
    };
    auto f = std::make_shared<Frames>();
    f->frames = std::make_unique<DeviceFrames>(ls, *f->noopt, rs, device);
    time->clock = f->frames->clock();
    time->device = f->frames->device();
    return [f, time](uint32_t frame, Accumulator& acc) {
      time->ms += f->frames->render(frame, acc).gpu_ms;
      ++time->frames;
    };
  };
}

DeviceRenderTotals render_on_device(const LoadedScene& ls, const Generator& generator, const RenderSettings& rs,
                                    const std::string& on, int frames, Accumulator& acc,
                                    const std::function<void(int)>& progress) {
  DeviceFrames device(ls, generator, rs, on);
  DeviceRenderTotals totals;
  totals.device = device.device();
  totals.clock = device.clock();
  for (int f = 0; f < frames; ++f) {
    const DeviceFrame d = device.render(static_cast<uint32_t>(f), acc);
    totals.gpu_ms += d.gpu_ms;
    add_stages(totals.stages, d.stages);
    totals.rays += d.rays();
    const auto mrays = [](double rays, double ms) { return ms > 0 ? rays / ms * 1e-3 : std::nan(""); };
    totals.frame_ms.push_back(d.gpu_ms);
    totals.first_mrays.push_back(mrays(d.stages.first_rays, d.stages.first_trace));
    totals.second_mrays.push_back(mrays(d.stages.second_rays, d.stages.second_trace));
    progress(f);
  }
  return totals;
}

}  // namespace raycoh
