// The modeled GPU clock of `converge`: how long each path-traced frame would take on the `simt` tracer's GPU
// (docs/simt-model.md), computed on the very rays the renderer traces. Modeled, not measured: reported in its own
// columns and never added to a measured time.
//
// How. After a timed frame (outside its timing), FrameModel renders the same frame index again through a
// ModelingTracer: hits come from the renderer's own tracer, so the second render is bit for bit the timed one
// (the path tracer is deterministic, shading/path_stages.h) and hands the tracer exactly the same batches, in
// the same order; each batch is also traced by the `simt` tracer, whose modeled kernel time is summed. The ray
// counts of the two renders are checked equal.
//
// Included: one trace launch per batch the frame traces (camera rays, the generator's secondary batch, each later
// bounce, each bounce's shadow rays), each replayed with cold caches (simt/timed_replay.h: a launch starts with
// empty L1s and L2), and the generator's stage as simt/pipeline_model.h models it (modeled_generation_ms: the
// G-buffer read and the batch written, the same bytes per ray for every generator).
// Not included: camera-ray generation, shading (next-event sampling, BSDF sampling, MIS weights, accumulation),
// the compaction between bounces and launch overheads. These are the same work for every generator up to the
// number of paths alive, so they shift the modeled frame time of all generators alike; the model times the
// trace, which is where the generators differ.
#pragma once

#include <cstdint>
#include <memory>

#include "generators/generator.h"
#include "scenes/scene.h"
#include "shading/image.h"
#include "shading/path_tracer.h"
#include "tracers/tracer.h"

namespace raycoh {

// Hits from `hits`; every batch also traced by `model` (a tracer with last_counters(), the `simt` tracer), whose
// modeled kernel times are summed.
class ModelingTracer final : public Tracer {
 public:
  ModelingTracer(Tracer& hits, Tracer& model);
  void trace(const Ray* rays, size_t count, Hit* hits) override;
  std::string params() const override { return hits_.params(); }
  // Modeled milliseconds and launches since the last reset().
  double modeled_ms() const { return ms_; }
  int launches() const { return launches_; }
  void reset() { ms_ = 0, launches_ = 0; }

 private:
  Tracer& hits_;
  Tracer& model_;
  std::vector<Hit> scratch_;
  double ms_ = 0;
  int launches_ = 0;
};

// One frame on the modeled GPU.
struct ModeledFrame {
  double gen_ms = 0;    // the generator's stage (modeled_generation_ms)
  double trace_ms = 0;  // every trace launch of the frame
  int launches = 0;
  double ms() const { return gen_ms + trace_ms; }
};

// One generator's frames on the model. scene, tracer and model must outlive it; model is the `simt` tracer made
// for this scene.
class FrameModel {
 public:
  FrameModel(const Scene& scene, Tracer& tracer, Tracer& model, std::unique_ptr<Generator> generator,
             const RenderSettings& settings);
  // Frame `frame` again on the model; `timed` is the timed render's stats of that frame (its ray counts must
  // match).
  ModeledFrame model(uint32_t frame, const FrameStats& timed);
  // Frame `frame` on the model without that check: the timed frame was rendered on another device (converge
  // --device cuda), whose rays are other samples of the same estimator; the model times the CPU's frame.
  ModeledFrame model(uint32_t frame);

 private:
  std::unique_ptr<Generator> generator_;
  ModelingTracer tracer_;
  const Tracer& model_;
  PathTracer pt_;
  Accumulator scratch_;
  size_t pixels_;
  FrameStats last_;  // the last modeled frame's render
};

}  // namespace raycoh
