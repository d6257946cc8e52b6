// `raycoh converge`'s run (harness/image/converge.cpp: the options, the render loop;
// harness/image/converge_summary.cpp: the ratios against the baseline, the summary CSV and the console tables).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "generators/generator.h"
#include "harness/image/converge.h"
#include "harness/image/denoise_eval.h"
#include "harness/image/device_clock.h"
#include "harness/image/frame_source.h"
#include "harness/image/gpu_clock.h"
#include "harness/image/render_common.h"
#include "records/converge_row.h"
#include "records/curves.h"
#include "records/record_csv.h"
#include "shading/metrics.h"
#include "shading/path_tracer.h"
#include "tracers/tracer.h"

namespace raycoh {

// <out stem>-summary.csv.
std::string summary_path_of(const ConvergeOptions& o);

// A generator's modeled GPU clock: its frames modeled on the `simt` tracer of --gpu-model, a sum of its own, never
// added to a measured time.
struct ModeledClock {
  std::unique_ptr<FrameModel> model;  // null without --gpu-model
  ModeledFrame last;                  // the last modeled frame
  double s = 0;                       // modeled GPU seconds so far
  std::vector<CurvePoint> curve;      // error against modeled seconds
};

// What every frame's error is measured against: the reference, the tone map resolved on it (the same for every
// generator), and the reference's own noise, from its half image.
struct ErrorBasis {
  ReferenceImage ref;
  ToneMap tm;
  std::optional<ReferenceNoise> noise;
};

// One generator's progress.
struct Run {
  std::string label;
  std::unique_ptr<FrameSource> source;  // its frames on --device's path tracer
  Accumulator acc;
  FrameStats total;
  int frames = 0;
  std::vector<CurvePoint> by_wall, by_trace;  // by_trace stays empty on the device (no trace time apart)
  bool active = true;
  ModeledClock gpu;     // absent (no model) without --gpu-model
  DeviceClock device;   // --device cuda: the device's GPU time (measured or simulated); inactive on the CPU
  AuxAccumulators aux;  // --denoise: the first hits' albedo and normal over the same frames
};

class ConvergeRun {
 public:
  ConvergeRun(const ConvergeOptions& o, const Provenance& p);
  // Both files already hold this very command's finished result: nothing is rendered.
  bool complete() const { return csv_.already_complete(); }
  void render();
  void summarize();

 private:
  bool render_round();
  ConvergeRow row_of(size_t gi, const SourcedFrame& f, const ErrorMetrics& m, bool modeled) const;
  // The denoised figures of the running mean into the row, at power-of-two frame counts (--denoise).
  void add_denoised(const Run& run, const Image& mean, ConvergeRow& row) const;
  // --shard: the generators whose rows this shard writes; it renders the baseline (0) too, for its ratios.
  bool owns(size_t gi) const { return owned_[gi]; }
  bool renders(size_t gi) const { return gi == 0 || owns(gi); }
  SummaryRow compare(const Run& run, const std::string& clock) const;
  std::vector<std::string> clocks() const;

  const ConvergeOptions& o_;
  Provenance provenance_;  // with this run's device
  // A convergence curve is one timed measurement: an interrupted run starts again rather than resuming. Both
  // files are opened (and locked) before anything is rendered.
  RecordCsv<ConvergeRow> csv_;
  RecordCsv<SummaryRow> summary_;
  std::vector<std::unique_ptr<Generator>> generators_;
  std::unique_ptr<LoadedScene> ls_;
  ErrorBasis against_;
  std::unique_ptr<Tracer> gpu_model_;  // the `simt` tracer of --gpu-model, null for none
  DenoiseEval denoise_;
  std::vector<Run> runs_;
  std::vector<bool> owned_;
  std::string fingerprint_;
};

}  // namespace raycoh
