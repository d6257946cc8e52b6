#include "harness/image/gpu_clock.h"

#include <fmt/format.h>

#include "core/error.h"
#include "simt/pipeline_model.h"

namespace raycoh {

ModelingTracer::ModelingTracer(Tracer& hits, Tracer& model) : hits_(hits), model_(model) {
  RAYCOH_CHECK(model.last_counters() != nullptr && model.gpu_model() != nullptr,
               "the modeling tracer needs a tracer with a GPU model (simt)");
}

void ModelingTracer::trace(const Ray* rays, size_t count, Hit* hits) {
  hits_.trace(rays, count, hits);
  if (count == 0) return;
  scratch_.resize(count);
  model_.trace(rays, count, scratch_.data());
  ms_ += model_.last_counters()->modeled.ms;
  ++launches_;
}

FrameModel::FrameModel(const Scene& scene, Tracer& tracer, Tracer& model, std::unique_ptr<Generator> generator,
                       const RenderSettings& settings)
    : generator_(std::move(generator)),
      tracer_(tracer, model),
      model_(model),
      pt_(scene, tracer_, *generator_, settings),
      scratch_(settings.width, settings.height),
      pixels_(size_t(settings.width) * size_t(settings.height)) {}

ModeledFrame FrameModel::model(uint32_t frame, const FrameStats& timed) {
  const ModeledFrame m = model(frame);
  RAYCOH_CHECK(
      last_.primary_rays == timed.primary_rays && last_.secondary_rays == timed.secondary_rays &&
          last_.bounce_rays == timed.bounce_rays && last_.shadow_rays == timed.shadow_rays,
      fmt::format("frame {} on the GPU model traced {} rays, the timed render {}", frame, last_.rays(), timed.rays()));
  return m;
}

ModeledFrame FrameModel::model(uint32_t frame) {
  tracer_.reset();
  const FrameStats& f = last_ = pt_.render_frame(frame, scratch_);
  ModeledFrame m;
  m.trace_ms = tracer_.modeled_ms();
  m.launches = tracer_.launches();
  m.gen_ms = modeled_generation_ms(*model_.gpu_model(), pixels_, f.secondary_rays);
  return m;
}

}  // namespace raycoh
