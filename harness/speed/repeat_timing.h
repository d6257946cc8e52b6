// The repeated timing of one measurement and what a row records of it: the median, the fastest, the median's
// interval and every repeat (records/speed_interval.h), for tracers timed on the host's clock or by their own
// device clock. Device pipelines record theirs in harness/speed/device_rows.h.
#pragma once

#include <cstdint>
#include <vector>

#include "encoders/reorder.h"
#include "generators/generator.h"
#include "records/experiment_row.h"

namespace raycoh {

// Every timed repeat of one measurement, in seconds, in the order they ran.
struct Timing {
  std::vector<double> samples_s;
  double median() const;
  double min() const;
};

// Times `repeats` calls of fn (fn returns its own time in seconds).
template <class Fn>
Timing time_repeats(Fn&& fn, int repeats) {
  Timing t;
  for (int r = 0; r < repeats; ++r) t.samples_s.push_back(fn());
  return t;
}

// The host pipeline's stages before the trace, each timed once per repeat (generation and reordering are
// deterministic: every repeat makes the same batch and order), ms, in the order they ran. Empty vectors: the
// stage did not run (a primary pass has none).
struct StageSamples {
  std::vector<double> gen_ms, key_ms, sort_ms, permute_ms;
  // Repeat r's generation + key + sort + permute (a stage with fewer samples gives its last).
  double overhead_ms(size_t r) const;
  size_t size() const;
};

// A host pass's generation, `repeats` times into `out` (deterministic: the same batch each time; `stats` are one
// generation's): each time, ms.
std::vector<double> time_generation(Generator& generator, const Scene& scene, const GBuffer& gbuffer, uint32_t seed,
                                    RayBatch& out, GenerationStats& stats, size_t repeats);
// A host pass's reordering (encoders/reorder.h), `repeats` times (the same order and batch each time): each time of
// each stage that ran into `stages` (key, sort; permute in physical mode). Returns whether the batch was reordered.
bool time_reordering(Encoder& encoder, const RayBatch& in, PermuteMode mode, RayBatch& sorted,
                     std::vector<uint32_t>& order, size_t repeats, StageSamples& stages);

// A row's times from its repeats: the trace's (trace_ms, trace_ms_min, mray_s, its interval and samples), each
// stage's median (gen_ms, key_ms, sort_ms, permute_ms; samples with two or more repeats) and the end to end: repeat
// r's stages + repeat r's trace, its median and interval. row.rays must be set. One repeat: no interval columns.
void set_host_times(ExperimentRow& row, const Timing& t, const StageSamples& stages);

// The interval columns of a row from its samples (trace_samples_ms, e2e_samples_ms): absent below two repeats.
void set_intervals(ExperimentRow& row);

}  // namespace raycoh
