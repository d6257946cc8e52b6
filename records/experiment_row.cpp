#include "records/experiment_row.h"

#include <algorithm>

#include "generators/generator.h"
#include "records/hw_columns.h"
#include "simt/timed_replay.h"

namespace raycoh {

namespace {

// The coherence counters and the GPU model's columns (modelling tracers), between the measured times and the
// device pipeline's columns.
void append_modeled_columns(Schema<ExperimentRow>& s) {
  using namespace csv_format;
  using R = ExperimentRow;
  const Schema<R> modeled = {
      column("simt_efficiency", &R::simt_efficiency, Optional<General>{}),
      column("node_simt_efficiency", &R::node_simt_efficiency, Optional<General>{}),
      column("lines_per_ray", &R::lines_per_ray, Optional<General>{}),
      column("fetches_per_ray", &R::fetches_per_ray, Optional<General>{}),
      column("l1_misses_per_ray", &R::l1_misses_per_ray, Optional<General>{}),
      column("l2_misses_per_ray", &R::l2_misses_per_ray, Optional<General>{}),
      column("dram_bytes_per_ray", &R::dram_bytes_per_ray, Optional<General>{}),
      column("modeled_ms", &R::modeled_ms, Optional<General>{}),
      column("modeled_mray_s", &R::modeled_mray_s, Optional<General>{}),
      column("modeled_e2e_ms", &R::modeled_e2e_ms, Optional<General>{}),
      column("modeled_e2e_mray_s", &R::modeled_e2e_mray_s, Optional<General>{}),
      column("modeled_limiter", &R::modeled_limiter, Text{}),
      column("modeled_l1_wavefronts_per_ray", &R::modeled_l1_wavefronts_per_ray, Optional<General>{}),
      column("modeled_l1_local_wavefronts_per_ray", &R::modeled_l1_local_wavefronts_per_ray, Optional<General>{}),
      column("modeled_gen_ms", &R::modeled_gen_ms, Optional<General>{}),
      column("modeled_key_ms", &R::modeled_key_ms, Optional<General>{}),
      column("modeled_sort_ms", &R::modeled_sort_ms, Optional<General>{}),
      column("modeled_permute_ms", &R::modeled_permute_ms, Optional<General>{}),
      column("modeled_gen_bytes", &R::modeled_gen_bytes, Optional<General>{}),
      column("modeled_key_bytes", &R::modeled_key_bytes, Optional<General>{}),
      column("modeled_sort_bytes", &R::modeled_sort_bytes, Optional<General>{}),
      column("modeled_permute_bytes", &R::modeled_permute_bytes, Optional<General>{}),
  };
  s.insert(s.end(), modeled.begin(), modeled.end());
}

}  // namespace

const Schema<ExperimentRow>& experiment_schema() {
  using namespace csv_format;
  using R = ExperimentRow;
  using Count = Optional<Integer<size_t>>;
  static const Schema<R> schema = [] {
    Schema<R> s = {
        column("scene", &R::scene, Text{}, Key::Yes),
        column("scene_triangles", &R::scene_triangles, Integer<size_t>{}),
        column("pass", &R::pass, Text{}, Key::Yes),
        column("method", &R::method, Text{}, Key::Yes),
        column("generator", &R::generator, Text{}),
        column("generator_params", &R::generator_params, Text{}, Key::Yes),
        column("tracer", &R::tracer, Text{}, Key::Yes),
        column("tracer_params", &R::tracer_params, Text{}, Key::Yes),
        column("bvh", &R::bvh, Text{}),
        column("width", &R::width, Integer<int>{}, Key::Yes),
        column("height", &R::height, Integer<int>{}, Key::Yes),
        column("frame", &R::frame, Integer<int>{}, Key::Yes),
        column("seed", &R::seed, Integer<uint32_t>{}, Key::Yes),
        column("rays", &R::rays, Integer<size_t>{}),
        column("gen_ms", &R::gen_ms, Fixed<4>{}),
        column("trace_ms", &R::trace_ms, Fixed<4>{}),
        column("trace_ms_min", &R::trace_ms_min, Fixed<4>{}),
        column("repeats", &R::repeats, Integer<int>{}, Key::Yes),
        column("mray_s", &R::mray_s, Fixed<3>{}),
        column("below_geometric", &R::below_geometric, Count{}),
        column("below_shading", &R::below_shading, Count{}),
        column("non_finite", &R::non_finite, Count{}),
        column("groups_diffuse", &R::groups_diffuse, Count{}),
        column("groups_glossy", &R::groups_glossy, Count{}),
        column("groups_hybrid", &R::groups_hybrid, Count{}),
        column("groups_independent", &R::groups_independent, Count{}),
        column("groups_world", &R::groups_world, Count{}),
        column("hybrid_mean_fallback", &R::hybrid_mean_fallback, Count{}),
        column("reused_rays", &R::reused_rays, Count{}),
        column("encoder", &R::encoder, Text{}),
        column("encoder_params", &R::encoder_params, Text{}, Key::Yes),
        column("permute", &R::permute, Text{}, Key::Yes),
        column("key_ms", &R::key_ms, Fixed<4>{}),
        column("sort_ms", &R::sort_ms, Fixed<4>{}),
        column("permute_ms", &R::permute_ms, Fixed<4>{}),
        column("e2e_ms", &R::e2e_ms, Fixed<4>{}),
        column("e2e_mray_s", &R::e2e_mray_s, Fixed<3>{}),
    };
    append_modeled_columns(s);
    const Schema<R> device = {
        column("pipeline", &R::pipeline, Text{}),
        column("gpu_e2e_ms", &R::gpu_e2e_ms, Optional<General>{}),
        column("gpu_e2e_mray_s", &R::gpu_e2e_mray_s, Optional<General>{}),
        column("trace_ms_lo", &R::trace_ms_lo, Optional<General>{}),
        column("trace_ms_hi", &R::trace_ms_hi, Optional<General>{}),
        column("e2e_ms_lo", &R::e2e_ms_lo, Optional<General>{}),
        column("e2e_ms_hi", &R::e2e_ms_hi, Optional<General>{}),
        column("interval_level", &R::interval_level, Optional<General>{}),
        column("trace_samples_ms", &R::trace_samples_ms, Numbers{}),
        column("e2e_samples_ms", &R::e2e_samples_ms, Numbers{}),
        column("gen_samples_ms", &R::gen_samples_ms, Numbers{}),
        column("key_samples_ms", &R::key_samples_ms, Numbers{}),
        column("sort_samples_ms", &R::sort_samples_ms, Numbers{}),
        column("permute_samples_ms", &R::permute_samples_ms, Numbers{}),
        column("scene_fingerprint", &R::scene_fingerprint, Text{}),
    };
    s.insert(s.end(), device.begin(), device.end());
    append_columns(s, gpu_provenance_schema(), &R::gpu);
    append_columns(s, provenance_schema(), &R::provenance);
    append_columns(s, recorded_schema(), &R::recorded);
    append_hw_columns(s);  // last, so that every column before keeps its place in files already written
    return s;
  }();
  return schema;
}

void set_recorded_params(ExperimentRow& row) {
  row.recorded = recorded_columns(row.generator, row.generator_params, row.tracer, row.tracer_params);
}

void set_recorded_params(ExperimentRow& row, const Generator& generator) {
  row.recorded = recorded_columns(row.generator, generator, row.tracer, row.tracer_params);
}

void set_generation(ExperimentRow& row, const GenerationStats& g) {
  row.below_geometric = g.below_geometric;
  row.below_shading = g.below_shading;
  row.non_finite = g.non_finite;
  row.groups_diffuse = g.groups[1];
  row.groups_glossy = g.groups[2];
  row.groups_hybrid = g.groups[3];
  row.groups_independent = g.groups[0];
  row.groups_world = g.groups[4];
  row.hybrid_mean_fallback = g.hybrid_mean_fallback;
  row.reused_rays = g.reused_rays;
}

GenerationStats generation_of(const ExperimentRow& row) {
  GenerationStats g;
  g.rays = row.rays;
  g.below_geometric = row.below_geometric.value_or(0);
  g.below_shading = row.below_shading.value_or(0);
  g.non_finite = row.non_finite.value_or(0);
  g.groups[1] = row.groups_diffuse.value_or(0);
  g.groups[2] = row.groups_glossy.value_or(0);
  g.groups[3] = row.groups_hybrid.value_or(0);
  g.groups[0] = row.groups_independent.value_or(0);
  g.groups[4] = row.groups_world.value_or(0);
  g.hybrid_mean_fallback = row.hybrid_mean_fallback.value_or(0);
  g.reused_rays = row.reused_rays.value_or(0);
  return g;
}

namespace {

void add_frame_times(const ExperimentRow& row, MeasuredSums& m) {
  const double rays = static_cast<double>(row.rays);
  const double e2e = row.gpu_e2e_ms.value_or(row.e2e_ms);
  m.trace_times[row.frame] = {row.trace_samples_ms.empty() ? std::vector<double>{row.trace_ms} : row.trace_samples_ms,
                              rays};
  m.e2e_times[row.frame] = {row.e2e_samples_ms.empty() ? std::vector<double>{e2e} : row.e2e_samples_ms, rays};
}

void add_measured(const ExperimentRow& row, MeasuredSums& m) {
  m.trace_s += row.trace_ms * 1e-3;
  m.gen_s += row.gen_ms * 1e-3;
  m.reorder_s += (row.key_ms + row.sort_ms + row.permute_ms) * 1e-3;
  m.e2e_s += row.e2e_ms * 1e-3;
  m.repeats = row.repeats;
  if (row.pipeline != "host") {  // device or fused: every stage on the device
    m.on_device = true;
    m.gpu_span_s += row.gpu_e2e_ms.value_or(0) * 1e-3;
  }
  add_frame_times(row, m);
}

void add_counters(const ExperimentRow& row, double rays, CounterSums& c) {
  if (!row.simt_efficiency) return;
  c.any = true;
  c.simt_eff_w += rays * *row.simt_efficiency;
  c.lines_w += rays * row.lines_per_ray.value_or(0);
  c.l1_w += rays * row.l1_misses_per_ray.value_or(0);
  c.l2_w += rays * row.l2_misses_per_ray.value_or(0);
  c.dram_w += rays * row.dram_bytes_per_ray.value_or(0);
}

void add_modeled(const ExperimentRow& row, ModeledSums& m) {
  if (!row.modeled_ms) return;
  m.any = true;
  m.trace_s += *row.modeled_ms * 1e-3;
  m.e2e_s += row.modeled_e2e_ms.value_or(0) * 1e-3;
  m.limiter = row.modeled_limiter;
  m.gen_s += row.modeled_gen_ms.value_or(0) * 1e-3;
  m.reorder_s +=
      (row.modeled_key_ms.value_or(0) + row.modeled_sort_ms.value_or(0) + row.modeled_permute_ms.value_or(0)) * 1e-3;
}

void add_hw(const ExperimentRow& row, double rays, HwCounterSums& h) {
  if (row.provenance.run_under == kHwCountersRunUnder) h.replayed = true;
  h.w.resize(std::max(h.w.size(), row.hw.size()), 0.0);
  h.rays.resize(h.w.size(), 0.0);
  for (size_t i = 0; i < row.hw.size(); ++i)
    if (row.hw[i]) h.w[i] += rays * *row.hw[i], h.rays[i] += rays;
}

}  // namespace

SpeedRatio measured_ratio(const Accumulated& base, const Accumulated& method, bool e2e) {
  return e2e ? paired_ratio(base.measured.e2e_times, method.measured.e2e_times)
             : paired_ratio(base.measured.trace_times, method.measured.trace_times);
}

ResultKey result_key(const ExperimentRow& row) {
  return result_key(row.tracer, row.tracer_params, row.bvh, row.recorded);
}

std::string fastest_modeled(const std::map<std::string, Accumulated>& sums, const std::vector<std::string>& methods) {
  const std::string* best = &methods.front();
  for (const std::string& m : methods)
    if (sums.at(m).modeled_e2e_mray_s() > sums.at(*best).modeled_e2e_mray_s()) best = &m;
  return *best;
}

std::string measured_top(const std::map<std::string, Accumulated>& sums, const std::vector<std::string>& methods) {
  std::vector<std::pair<std::string, const FrameSeries*>> ranked;
  for (const std::string& m : methods) ranked.emplace_back(m, &sums.at(m).measured.e2e_times);
  return top_of_ranking(ranked, sums.at("noopt").measured.e2e_times);
}

void accumulate(const ExperimentRow& row, int frames, SceneResult& res) {
  const ResultKey key = result_key(row);
  if (std::find(res.tracers.begin(), res.tracers.end(), key) == res.tracers.end()) res.tracers.push_back(key);
  const bool first_tracer = key == res.tracers.front();
  Accumulated& acc = res.by_tracer[key][row.method];
  const double rays = static_cast<double>(row.rays);
  acc.rays += rays;
  ++acc.frames;
  add_measured(row, acc.measured);
  add_counters(row, rays, acc.counters);
  add_modeled(row, acc.model);
  add_hw(row, rays, acc.hw);
  if (row.pass != "secondary" || !first_tracer) return;
  res.rays_per_frame = rays;
  res.gen_ms[row.method] += row.gen_ms / frames;
  merge_stats(res.generation[row.method], generation_of(row));
}

void set_counters(ExperimentRow& r, const CoherenceCounters& c, const ModeledStages& stages) {
  r.simt_efficiency = c.simt_efficiency();
  r.node_simt_efficiency = c.node_simt_efficiency();
  r.lines_per_ray = c.per_ray(c.node_lines + c.triangle_lines);
  r.fetches_per_ray = c.fetches_per_ray();
  r.l1_misses_per_ray = c.l1_misses_per_ray();
  r.l2_misses_per_ray = c.l2_misses_per_ray();
  r.dram_bytes_per_ray = c.dram_bytes_per_ray();
  if (c.modeled.ms <= 0) return;
  const double e2e_ms = c.modeled.ms + stages.gen_ms + stages.reorder_ms();
  r.modeled_ms = c.modeled.ms;
  r.modeled_mray_s = c.modeled_mray_s();
  r.modeled_e2e_ms = e2e_ms;
  r.modeled_e2e_mray_s = static_cast<double>(r.rays) / e2e_ms * 1e-3;
  r.modeled_limiter = modeled_limiter(c.modeled);
  r.modeled_l1_wavefronts_per_ray = c.per_ray(c.modeled.l1_wavefronts);
  r.modeled_l1_local_wavefronts_per_ray = c.per_ray(c.modeled.l1_local_wavefronts);
  r.modeled_gen_ms = stages.gen_ms;
  r.modeled_key_ms = stages.key_ms;
  r.modeled_sort_ms = stages.sort_ms;
  r.modeled_permute_ms = stages.permute_ms;
  r.modeled_gen_bytes = stages.gen_bytes;
  r.modeled_key_bytes = stages.key_bytes;
  r.modeled_sort_bytes = stages.sort_bytes;
  r.modeled_permute_bytes = stages.permute_bytes;
}

}  // namespace raycoh
