// What an experiment (harness/speed/experiment.cpp) checks and builds before it measures: its options, the rule its
// resumed rows must meet, and per scene the scene, BVH, tracers and encoders. Internal to the experiment loop.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "encoders/encoder.h"
#include "generators/generator.h"
#include "harness/speed/experiment.h"
#include "records/csv.h"
#include "scenes/scene.h"
#include "tracers/device_pipeline.h"
#include "tracers/tracer.h"

namespace raycoh {

// The primary pass uses the compact 8x8 tile order every generator uses by default.
inline constexpr int kPrimaryTile = 8;
inline constexpr const char* kPrimaryParams = "order=tile,tile=8x8";

// Checks every option, then makes one generator per method: every name and parameter is checked before anything
// is measured.
std::vector<std::unique_ptr<Generator>> checked_generators(const ExperimentOptions& o);

// What rows of an earlier run must hold to be this run's (records/csv.h): everything known before a scene is
// loaded. Tracer and encoder parameters are known only then; rows differing there are found at the end (run()).
ResumeRule experiment_rule(const ExperimentOptions& o, const std::vector<std::unique_ptr<Generator>>& generators,
                           const Provenance& p);

// The defaults of --repeat: a GPU's times from 9 repeats (a 96% median interval), the CPU's from 7 (98%); one run
// of a tracer whose figure is deterministic: counting and modelling tracers and simulated GPUs.
inline constexpr int kDeviceRepeats = 9, kHostRepeats = 7;
// Timed repeats of `tracer` in this run: --repeat when given, else the default above (`model`: the tracer counts).
int tracer_repeats(const ExperimentOptions& o, const PluginSpec& tracer, bool model);

// One scene with its BVH, tracers and encoders; tracers keep references to scene and BVH, so it never moves.
struct SceneSetup {
  std::string fingerprint;
  Scene scene;
  Bvh bvh;
  std::vector<std::unique_ptr<Tracer>> tracers;
  std::vector<std::unique_ptr<Encoder>> encoders;  // one per method
  std::unique_ptr<Tracer> gbuffer_tracer;
  std::vector<bool> warmed, models;        // models: tracers with coherence counters (deterministic, run once)
  std::vector<int> repeats;                // per tracer: tracer_repeats
  std::vector<GpuProvenance> gpu;          // per tracer: its GPU's facts (records/provenance.h), empty on the CPU
  std::vector<DevicePipeline*> pipelines;  // per tracer: its device pipeline, or null (it traces host-made batches)
  // Loads and builds; keys receives each tracer's result key (records/result_key.h). Throws raycoh::Error when a
  // tracer's device pipeline has no device version of a method's generator or encoder (DevicePipeline::refusal).
  SceneSetup(const std::string& spec, const ExperimentOptions& o,
             const std::vector<std::unique_ptr<Generator>>& generators, std::vector<ResultKey>& keys);
  SceneSetup(const SceneSetup&) = delete;
  SceneSetup& operator=(const SceneSetup&) = delete;
};

}  // namespace raycoh
