// The frames of a render on the CPU or the device (frame_source.h).
#include "harness/image/frame_source.h"

#include <chrono>

#include "harness/image/render_device.h"

namespace raycoh {

FrameSource::FrameSource(const std::string& device, const LoadedScene& ls, Generator& generator,
                         const RenderSettings& rs)
    : cpu_(std::make_unique<PathTracer>(ls.scene, *ls.tracer, generator, rs)) {
  if (raycoh::on_device(device)) device_ = std::make_unique<DeviceFrames>(ls, generator, rs, device);
}

FrameSource::~FrameSource() = default;

SourcedFrame FrameSource::render(uint32_t frame, Accumulator& acc, AuxAccumulators* aux) {
  SourcedFrame out;
  if (!device_) {
    out.stats = cpu_->render_frame(frame, acc, aux);
    return out;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const uint64_t non_finite = acc.non_finite_samples();
  const DeviceFrame d = device_->render(frame, acc);
  out.stats.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.stats.primary_rays = d.primary_rays;
  out.stats.secondary_rays = d.secondary_rays;
  out.stats.bounce_rays = d.bounce_rays;
  out.stats.shadow_rays = d.shadow_rays;
  out.stats.generation = d.generation;
  out.stats.hybrid_diffuse = d.hybrid_diffuse;
  out.stats.non_finite = acc.non_finite_samples() - non_finite;
  out.gpu_ms = d.gpu_ms;
  out.gpu_stages = d.stages;
  if (aux) cpu_->first_hits(frame, *aux);  // outside the frame's wall time, as the denoiser is
  return out;
}

std::string FrameSource::clock() const { return device_ ? device_->clock() : std::string(); }

std::string FrameSource::device_name() const { return device_ ? device_->device() : std::string("cpu"); }

}  // namespace raycoh
