// The measurement loop every experiment shares (`table`, `sweep`): per scene, load, build the BVH once, then
// per frame trace the primary rays (G-buffer + the coherent bound), and for every method generate the
// secondary batch and trace it with every tracer. One CSV row per scene x pass x method x tracer x frame
// (schema in results/README.md); rows are flushed as they are measured.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/params.h"
#include "core/ray_batch.h"
#include "harness/provenance.h"

namespace raycoh {

// A way of making the secondary batch coherent: a generator, optionally followed by a reordering encoder.
struct Method {
  std::string label;  // row name in the console tables: "ours", "noopt+origin", ...
  PluginSpec generator;
  PluginSpec encoder{"none", ""};
};

struct ExperimentOptions {
  std::vector<std::string> scenes;
  std::vector<Method> methods;  // must contain the baseline labelled "noopt"
  std::vector<PluginSpec> tracers;
  int width = 320, height = 240;
  int frames = 4;
  uint32_t seed = 1;
  int repeats = 3;
  std::string permute = "physical";  // physical | indirect: how a reordering is applied (encoders/permute.h)
  std::string out;
};

// Sums over frames for one tracer and method.
struct Accumulated {
  double rays = 0, trace_s = 0, gen_s = 0, reorder_s = 0;  // reorder = key + sort + permute
  int frames = 0;
  double mray_s() const { return trace_s > 0 ? rays / trace_s * 1e-6 : 0.0; }
  // End to end: generation + reordering + trace.
  double e2e_s() const { return gen_s + reorder_s + trace_s; }
  double e2e_mray_s() const { return e2e_s() > 0 ? rays / e2e_s() * 1e-6 : 0.0; }
  double overhead_share() const { return e2e_s() > 0 ? (gen_s + reorder_s) / e2e_s() : 0.0; }
  // Coherence counters of modelling tracers (`simt`), per ray, weighted by rays over frames.
  bool has_counters = false;
  double simt_eff_w = 0, lines_w = 0, l1_w = 0, l2_w = 0, dram_w = 0, cost_w = 0;
  double per_ray(double weighted) const { return rays > 0 ? weighted / rays : 0.0; }
};

struct SceneResult {
  std::string scene;
  size_t triangles = 0;
  double rays_per_frame = 0;
  std::vector<std::string> tracer_labels;
  std::map<std::string, std::map<std::string, Accumulated>> by_tracer;  // tracer label -> method label ("primary" too)
  std::map<std::string, GenerationStats> generation;                    // method label -> sums over frames
  std::map<std::string, double> gen_ms;                                 // method label -> mean per frame
};

// Throws raycoh::Error on bad input; rows measured before the error stay in "<out>.partial".
std::vector<SceneResult> run_experiment(const ExperimentOptions& options, const Provenance& provenance);

// Column names of the experiment CSV (the provenance columns follow).
std::vector<std::string> experiment_columns();

// Adds plain `noopt` in front unless a method is labelled "noopt".
void ensure_baseline(std::vector<Method>& methods);

// Every generator with every encoder, labelled "generator" (encoder none) or "generator+encoder".
std::vector<Method> method_product(const std::vector<PluginSpec>& generators, const std::vector<PluginSpec>& encoders);

}  // namespace raycoh
