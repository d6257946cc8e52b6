// The whole per-frame ray pipeline on a tracer's own device (docs/design.md section 1): camera rays, their G-buffer,
// secondary generation, keys, sort, permutation and trace, each stage timed there. A tracer that has one returns
// it from Tracer::device_pipeline() (the `cuda` tracer with pipeline=device, cuda/device_pipeline.h); the experiment
// loop (harness/speed/experiment.cpp) then runs every row of that tracer through it instead of tracing host-made
// batches. Plain C++: the interface names no device API.
//
// Measured, never modeled: every time below is the device's own clock (CUDA events), and no host time is added
// to it. The G-buffer is made from the primary hits once per frame, before the secondary passes, on the device and
// kept there (cuda: the G-buffer kernel, equal to make_gbuffer bit for bit); not timed, in no stage: it is not a
// generator's overhead on either side.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/ray.h"
#include "core/ray_batch.h"
#include "encoders/permute.h"
#include "generators/primary.h"

namespace raycoh {

class Generator;
class Encoder;

// One pass's stage times on the device, in milliseconds (CUDA events). span_ms is one event pair around the whole
// pass, from before the first generation kernel to after the trace kernel: the stages plus what lies between them
// (launch gaps, the few zeroing memsets); it is measured, not the sum of the stages. Stages a pass does not run
// (the primary pass's keys, `none`'s sort, indirect mode's gather) are 0.
// A fused pass (cuda:pipeline=fused) makes and traces its rays in one kernel: its trace_ms holds the generation too.
struct DeviceStageTimes {
  double gen_ms = 0, key_ms = 0, sort_ms = 0, permute_ms = 0, trace_ms = 0;
  double span_ms = 0;
  bool fused = false;
  double stages_ms() const { return gen_ms + key_ms + sort_ms + permute_ms + trace_ms; }
};

// Median of each field over the passes (each field on its own; passes must not be empty), and the fastest trace.
DeviceStageTimes median_stage_times(std::vector<DeviceStageTimes> passes, double* trace_min_ms = nullptr);

class DevicePipeline {
 public:
  virtual ~DevicePipeline() = default;

  // Empty when the generator (registered as generator_name) and the encoder have device versions; otherwise one
  // line naming the one that has none and what is valid. Needs no device (asked before anything is measured).
  virtual std::string refusal(const std::string& generator_name, const Generator& generator,
                              const Encoder& encoder) const = 0;

  // Camera rays made on the device in tile order (tile_w x tile_h tiles, row-major inside), traced there. Times:
  // gen_ms (camera rays), trace_ms, span_ms.
  virtual DeviceStageTimes primary(int width, int height, int tile_w, int tile_h, uint32_t seed, uint32_t frame,
                                   bool jitter) = 0;
  // The G-buffer of the last primary pass, made where the pass left its rays and hits and kept there for
  // secondary() (nothing is downloaded; not timed).
  virtual void first_hits_gbuffer() = 0;
  // That G-buffer downloaded (tests and checks): make_gbuffer of download_primary's rays and hits, with its table.
  virtual GBuffer download_gbuffer() const = 0;

  // One secondary pass over the uploaded G-buffer: generation with generator's configuration, then (for an
  // encoder with keys) keys, stable radix sort and, in physical mode, the gather of every batch array, then the
  // trace (indirect mode: lane i traces ray order[i]). stats: the generation statistics (the CPU generator's).
  virtual DeviceStageTimes secondary(const Generator& generator, const Encoder& encoder, PermuteMode mode,
                                     uint32_t seed, GenerationStats& stats) = 0;

  // The last passes' results, downloaded (tests and checks): primary rays and hits; the generated batch, the sort
  // order (empty without keys), the physically permuted batch (empty unless physical with keys) and the hits in
  // trace order (hits[i] belongs to permuted ray i, ray order[i] in indirect mode, else generated ray i).
  virtual void download_primary(PixelRays& rays, std::vector<Hit>& hits) const = 0;
  virtual void download_secondary(RayBatch& generated, std::vector<uint32_t>& order, RayBatch& permuted,
                                  std::vector<Hit>& hits) const = 0;
};

}  // namespace raycoh
