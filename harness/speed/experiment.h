// The measurement loop every experiment shares (`table`, `sweep`): per scene, load, build the BVH once, then
// per frame trace the primary rays (G-buffer + the coherent bound), and for every method generate the
// secondary batch and trace it with every tracer. One CSV row per scene x pass x method x tracer x frame
// (records/experiment_row.h, results/README.md); rows are flushed as they are measured.
#pragma once

#include <string>
#include <vector>

#include "core/params.h"
#include "records/experiment_row.h"
#include "records/provenance.h"
#include "records/shard.h"

namespace raycoh {

// A way of making the secondary batch coherent: a generator, optionally followed by a reordering encoder.
struct Method {
  std::string label;  // row name in the console tables: "ours", "noopt+origin", ...
  PluginSpec generator;
  PluginSpec encoder{"none", ""};
};

// The settings every experiment command shares; table.h and sweep.h embed them. run_experiment checks every
// value (the one validation layer) and names the option in its error.
struct ExperimentOptions {
  std::vector<std::string> scenes;
  std::vector<Method> methods;                   // must contain the baseline labelled "noopt"
  std::vector<PluginSpec> tracers{{"cpu", ""}};  // `auto`: cuda with a GPU, else cpu and simt
  int width = 320, height = 240;                 // --res, each in [1, 16384]
  int frames = 4;                                // --frames [1, 100000]
  uint32_t seed = 1;                             // --seed
  // --repeat [1, 1000]: timed traces (device passes) per batch, the median and its interval reported; 0: each
  // tracer's default (tracer_repeats, harness/speed/experiment_setup.h).
  int repeats = 0;
  std::string permute = "physical";  // physical | indirect: how a reordering is applied (encoders/permute.h)
  std::string out;
  bool force = false;  // --force: replace what --out and <out>.partial hold instead of resuming or refusing
  Shard shard;         // --shard I/N: only this shard's scene x frame x method units (records/shard.h)
};

// Throws raycoh::Error on bad input; rows measured before the error stay in "<out>.partial". A shard's results
// hold only its own units (a scene none of whose units it owns is neither loaded nor listed).
std::vector<SceneResult> run_experiment(const ExperimentOptions& options, const Provenance& provenance);

// `auto` replaced by the tracers it stands for.
std::vector<PluginSpec> expand_auto(const std::vector<PluginSpec>& tracers);

// Adds plain `noopt` in front unless a method is labelled "noopt".
void ensure_baseline(std::vector<Method>& methods);

// Every generator with every encoder, labelled "generator" (encoder none) or "generator+encoder".
std::vector<Method> method_product(const std::vector<PluginSpec>& generators, const std::vector<PluginSpec>& encoders);

}  // namespace raycoh
