// The record of one experiment measurement (`table`, `sweep`): one row per scene x pass x method x tracer x frame,
// its CSV column table (results/README.md) and the per-scene sums the console tables are printed from.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/ray_batch.h"
#include "records/provenance.h"
#include "records/recorded_columns.h"
#include "records/schema.h"
#include "records/speed_interval.h"
#include "simt/pipeline_model.h"
#include "tracers/tracer.h"

namespace raycoh {

struct ExperimentRow {
  std::string scene;
  size_t scene_triangles = 0;
  std::string pass;  // "primary" or "secondary"
  std::string method, generator, generator_params, tracer, tracer_params;
  std::string bvh;  // the tracer's acceleration structure (Tracer::bvh_layout)
  int width = 0, height = 0, frame = 0;
  uint32_t seed = 0;
  size_t rays = 0;
  double gen_ms = 0, trace_ms = 0, trace_ms_min = 0;
  int repeats = 0;
  double mray_s = 0;
  // Generation statistics of the secondary batch (absent for the primary pass).
  std::optional<size_t> below_geometric, below_shading, non_finite, groups_diffuse, groups_glossy, groups_hybrid,
      groups_independent, groups_world, hybrid_mean_fallback, reused_rays;
  std::string encoder, encoder_params, permute;
  double key_ms = 0, sort_ms = 0, permute_ms = 0, e2e_ms = 0, e2e_mray_s = 0;
  // Coherence counters per ray of modelling tracers (`simt`); absent for timing tracers.
  std::optional<double> simt_efficiency, node_simt_efficiency, lines_per_ray, fetches_per_ray, l1_misses_per_ray,
      l2_misses_per_ray, dram_bytes_per_ray;
  // The GPU timing model of modelling tracers (`simt`): modeled, not measured, never mixed with the columns
  // above. The trace kernel (simt/timed_replay.h), then generation + key + sort + permute + trace, all modeled
  // on the tracer's preset (simt/pipeline_model.h); the port that bounded the trace kernel.
  std::optional<double> modeled_ms, modeled_mray_s, modeled_e2e_ms, modeled_e2e_mray_s;
  std::string modeled_limiter;
  // The timing model's L1 pipeline wavefronts per ray (all memory instructions; the local-memory ones), to set
  // beside a GPU's counted wavefronts (Nsight Compute's l1tex__data_pipe_lsu_wavefronts).
  std::optional<double> modeled_l1_wavefronts_per_ray, modeled_l1_local_wavefronts_per_ray;
  // The modeled stages summed into modeled_e2e_ms (modelling tracers only), to set beside measured GPU stages.
  std::optional<double> modeled_gen_ms, modeled_key_ms, modeled_sort_ms, modeled_permute_ms;
  // The DRAM bytes each of those stages is modeled to move: a measured stage's traffic bound is these bytes over
  // the GPU's copy bandwidth (scripts/gpu-check's stage table).
  std::optional<double> modeled_gen_bytes, modeled_key_bytes, modeled_sort_bytes, modeled_permute_bytes;
  // Where the batch was made, reordered and timed: "host" (generation, keys, sort and permutation on the CPU,
  // steady_clock; the trace by the tracer's clock) or "device" (tracers/device_pipeline.h: every stage on the
  // GPU, CUDA events; gen_ms .. trace_ms and e2e_ms are then measured GPU times). gpu_e2e_ms: on device rows of
  // timing runs, one event pair around the whole pass, measured (not the sum of the stages).
  std::string pipeline = "host";
  std::optional<double> gpu_e2e_ms, gpu_e2e_mray_s;
  // Measured times' intervals (records/speed_interval.h), on rows of timing tracers with two or more repeats: the
  // trace's and the end to end's median interval at coverage interval_level, and every repeat's times (ms). End to
  // end per repeat is the measured span on device rows (gpu_e2e_ms), else generation + reordering (timed once) +
  // that repeat's trace. The table's ratio intervals are computed from the repeats.
  std::optional<double> trace_ms_lo, trace_ms_hi, e2e_ms_lo, e2e_ms_hi, interval_level;
  std::vector<double> trace_samples_ms, e2e_samples_ms;
  // Device pipelines' stages, every timed pass (ms; a stage that did not run: empty), for their intervals.
  std::vector<double> gen_samples_ms, key_samples_ms, sort_samples_ms, permute_samples_ms;
  std::string scene_fingerprint;  // shading/reference.h scene_fingerprint: `merge` refuses shards of other files
  GpuProvenance gpu;              // the GPU of a measured GPU row (records/provenance.h), empty elsewhere
  Provenance provenance;
  RecordedColumns recorded;  // tile_w .. mode (records/recorded_columns.h)
  // The GPU's own counters of the trace kernels, measured (`cuda:counters=hw`, records/hw_columns.h), the last
  // columns: one value per hw_column_names() entry, in that order; empty on every other row and where they could
  // not be read.
  std::vector<std::optional<double>> hw;
};

// The experiment CSV's columns, in file order, provenance last.
const Schema<ExperimentRow>& experiment_schema();

// The typed columns (tile_w .. mode) from the row's generator, generator_params, tracer and tracer_params.
void set_recorded_params(ExperimentRow& row);
// The same with the generator that made the row's batch: its typed layout where it gives one (K, tile, order not
// read back from generator_params).
void set_recorded_params(ExperimentRow& row, const Generator& generator);

// Copies the generation statistics into / out of a row.
void set_generation(ExperimentRow& row, const GenerationStats& g);
// The coherence counters of a counting tracer and, where its timing model ran, the modeled kernel and the
// modeled stages (never added to a measured column).
void set_counters(ExperimentRow& row, const CoherenceCounters& c, const ModeledStages& stages);
GenerationStats generation_of(const ExperimentRow& row);

// Measured times of one tracer and method, summed over frames (seconds).
struct MeasuredSums {
  double trace_s = 0, gen_s = 0, reorder_s = 0;  // reorder = key + sort + permute
  // End to end: generation + reordering + trace, as each row recorded it (e2e_ms: the median over repeats of
  // their sums).
  double e2e_s = 0;
  int repeats = 0;  // timed repeats per frame (of the last row)
  // Device pipelines (measured GPU): the pass's span; the stages' sums are the fields above.
  bool on_device = false;
  double gpu_span_s = 0;
  // Every repeat by frame (a row without repeats: its median alone), for the ratio intervals: the trace, and end
  // to end (device pipelines: the measured span).
  FrameSeries trace_times, e2e_times;
};

// Coherence counters of counting tracers (`simt`, `cuda:counters=on`), each weighted by rays over frames.
struct CounterSums {
  bool any = false;
  double simt_eff_w = 0, lines_w = 0, l1_w = 0, l2_w = 0, dram_w = 0;
};

// The GPU timing model's figures (modelling tracers), modeled seconds summed over frames, never mixed with the
// measured ones: the trace kernel, end to end, and the modeled stages (generation, key + sort + permute).
struct ModeledSums {
  bool any = false;
  double trace_s = 0, e2e_s = 0, gen_s = 0, reorder_s = 0;
  std::string limiter;  // of the last frame
};

// Rows whose kernels CUPTI replayed (run_under cupti-counters: no timings) and their measured hw columns, per
// hw_column_names() entry: the sum of value x rays over the rows holding it, and those rows' rays.
struct HwCounterSums {
  bool replayed = false;
  std::vector<double> w, rays;
  std::optional<double> value(size_t i) const {
    return i < rays.size() && rays[i] > 0 ? std::optional<double>(w[i] / rays[i]) : std::nullopt;
  }
};

// Sums over frames for one tracer and method: what the console tables print live and the report reads back from
// a CSV (records/experiment_sums.h), one aggregator.
struct Accumulated {
  double rays = 0;
  int frames = 0;
  MeasuredSums measured;
  CounterSums counters;
  ModeledSums model;
  HwCounterSums hw;

  double mray_s() const { return mray_s_of(measured.trace_s); }
  double e2e_mray_s() const { return mray_s_of(measured.e2e_s); }
  double gpu_span_mray_s() const { return mray_s_of(measured.gpu_span_s); }
  double overhead_share() const {
    return measured.e2e_s > 0 ? (measured.gen_s + measured.reorder_s) / measured.e2e_s : 0.0;
  }
  double modeled_mray_s() const { return mray_s_of(model.trace_s); }
  double modeled_e2e_mray_s() const { return mray_s_of(model.e2e_s); }
  double modeled_overhead_share() const { return model.e2e_s > 0 ? 1.0 - model.trace_s / model.e2e_s : 0.0; }
  // Trace only or end to end, measured or modeled, MRay/s.
  double speed(bool modeled, bool e2e) const {
    return modeled ? (e2e ? modeled_e2e_mray_s() : modeled_mray_s()) : (e2e ? e2e_mray_s() : mray_s());
  }
  double per_ray(double weighted) const { return rays > 0 ? weighted / rays : 0.0; }
  double mray_s_of(double seconds) const { return seconds > 0 ? rays / seconds * 1e-6 : 0.0; }
};

// Speed of `method` over `base` with its paired interval (records/speed_interval.h), over the frames both hold:
// the trace, or end to end (e2e; device pipelines: the measured span).
SpeedRatio measured_ratio(const Accumulated& base, const Accumulated& method, bool e2e);

// Which of `methods` is fastest end to end, over one scene's sums of one tracer (method label -> sums, noopt among
// them), as the table's closing lines and the report name it. Modeled: the highest modeled speed (the first on a
// tie). Measured: the top of the paired-interval ranking against noopt (records/speed_interval.h top_of_ranking).
std::string fastest_modeled(const std::map<std::string, Accumulated>& sums, const std::vector<std::string>& methods);
std::string measured_top(const std::map<std::string, Accumulated>& sums, const std::vector<std::string>& methods);

struct SceneResult {
  std::string scene;
  size_t triangles = 0;
  double rays_per_frame = 0;
  std::vector<ResultKey> tracers;                                     // in run (or file) order
  std::map<ResultKey, std::map<std::string, Accumulated>> by_tracer;  // tracer -> method label ("primary" too)
  std::map<std::string, GenerationStats> generation;                  // method label -> sums over frames
  std::map<std::string, double> gen_ms;                               // method label -> mean per frame
};

// The key of a row's results: its tracer, typed preset and mode, bvh and tracer_params.
ResultKey result_key(const ExperimentRow& row);

// Adds one row (measured now or resumed) to the scene's sums under result_key(row), a tracer not yet in
// res.tracers last. The generation statistics are the same in every tracer's row of a batch, so only the rows of
// the first tracer count them.
void accumulate(const ExperimentRow& row, int frames, SceneResult& res);

}  // namespace raycoh
