#include "harness/speed/repeat_timing.h"

#include <algorithm>
#include <chrono>

#include "records/speed_interval.h"

namespace raycoh {

double Timing::median() const { return median_interval(samples_s).median; }

double Timing::min() const { return samples_s.empty() ? 0.0 : *std::min_element(samples_s.begin(), samples_s.end()); }

namespace {

double sample(const std::vector<double>& v, size_t r) { return v.empty() ? 0.0 : v[std::min(r, v.size() - 1)]; }

double median_of(const std::vector<double>& v) { return v.empty() ? 0.0 : median_interval(v).median; }

}  // namespace

double StageSamples::overhead_ms(size_t r) const {
  return sample(gen_ms, r) + sample(key_ms, r) + sample(sort_ms, r) + sample(permute_ms, r);
}

size_t StageSamples::size() const {
  return std::max({gen_ms.size(), key_ms.size(), sort_ms.size(), permute_ms.size()});
}

std::vector<double> time_generation(Generator& generator, const Scene& scene, const GBuffer& gbuffer, uint32_t seed,
                                    RayBatch& out, GenerationStats& stats, size_t repeats) {
  std::vector<double> ms;
  for (size_t r = 0; r < repeats; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    generator.generate(scene, gbuffer, seed, out, stats);  // each call resets stats
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  return ms;
}

bool time_reordering(Encoder& encoder, const RayBatch& in, PermuteMode mode, RayBatch& sorted,
                     std::vector<uint32_t>& order, size_t repeats, StageSamples& stages) {
  bool reordered = false;
  for (size_t r = 0; r < repeats; ++r) {
    ReorderTimings t;
    reordered = reorder(encoder, in, mode, sorted, order, t);
    if (!reordered) break;  // no keys: nothing to time
    stages.key_ms.push_back(t.key_ms);
    stages.sort_ms.push_back(t.sort_ms);
    if (mode == PermuteMode::Physical) stages.permute_ms.push_back(t.permute_ms);
  }
  return reordered;
}

void set_host_times(ExperimentRow& row, const Timing& t, const StageSamples& stages) {
  const double rays = static_cast<double>(row.rays);
  const double median_s = t.median();
  row.trace_ms = median_s * 1e3;
  row.trace_ms_min = t.min() * 1e3;
  row.mray_s = median_s > 0 ? rays / median_s * 1e-6 : 0.0;
  row.gen_ms = median_of(stages.gen_ms);
  row.key_ms = median_of(stages.key_ms);
  row.sort_ms = median_of(stages.sort_ms);
  row.permute_ms = median_of(stages.permute_ms);
  row.e2e_ms = row.gen_ms + row.key_ms + row.sort_ms + row.permute_ms + row.trace_ms;
  row.trace_samples_ms.clear();
  row.e2e_samples_ms.clear();
  if (t.samples_s.size() >= 2) {
    for (size_t r = 0; r < t.samples_s.size(); ++r) {
      row.trace_samples_ms.push_back(t.samples_s[r] * 1e3);
      row.e2e_samples_ms.push_back(stages.overhead_ms(r) + t.samples_s[r] * 1e3);
    }
    if (stages.size() >= 2) {
      row.gen_samples_ms = stages.gen_ms;
      row.key_samples_ms = stages.key_ms;
      row.sort_samples_ms = stages.sort_ms;
      row.permute_samples_ms = stages.permute_ms;
    }
    row.e2e_ms = median_of(row.e2e_samples_ms);
    set_intervals(row);
  }
  row.e2e_mray_s = row.e2e_ms > 0 ? rays / row.e2e_ms * 1e-3 : 0.0;
}

void set_intervals(ExperimentRow& row) {
  if (row.trace_samples_ms.size() < 2) return;
  const MedianInterval trace = median_interval(row.trace_samples_ms);
  row.trace_ms_lo = trace.lo;
  row.trace_ms_hi = trace.hi;
  row.interval_level = trace.level;
  if (row.e2e_samples_ms.size() < 2) return;
  const MedianInterval e2e = median_interval(row.e2e_samples_ms);
  row.e2e_ms_lo = e2e.lo;
  row.e2e_ms_hi = e2e.hi;
}

}  // namespace raycoh
