// The speed stage of `raycoh tune`; see harness/tune/tune_speed.h.
#include "harness/tune/tune_speed.h"

#include <fmt/format.h>

#include "core/error.h"
#include "harness/speed/experiment.h"
#include "records/experiment_sums.h"
#include "records/result_csv.h"
#include "records/schema.h"
#include "simt/gpu_model.h"
#if defined(RAYCOH_HAVE_CUDA)
#include "cuda/cuda_device.h"
#endif

namespace raycoh {

namespace {

ExperimentOptions speed_options(const TuneOptions& o, const std::vector<std::string>& methods, uint32_t seed,
                                const std::string& out) {
  ExperimentOptions e;
  e.scenes = {o.scene};
  e.methods = {{"noopt", {"noopt", ""}}};
  for (const std::string& m : methods) e.methods.push_back({m, parse_plugin_spec(m)});
  e.tracers = {o.speed.tracer};
  e.width = o.width;
  e.height = o.height;
  e.frames = o.speed.frames;
  e.seed = seed;
  e.repeats = o.speed.repeats;
  e.out = out;
  e.force = o.force;
  e.shard = o.shard;
  return e;
}

// One row's times of the ranked figure, in ms: a model's modeled time; a measured row's every repeat (its median
// alone when it has none): the trace, or end to end (device pipelines: the measured span).
std::vector<double> row_times(const ResultCsv& c, const std::vector<std::string>& r, bool modeled, bool e2e) {
  if (modeled) return {c.num(r, e2e ? "modeled_e2e_ms" : "modeled_ms")};
  const std::vector<double> samples = csv_format::Numbers::read(c.get(r, e2e ? "e2e_samples_ms" : "trace_samples_ms"));
  if (!samples.empty()) return samples;
  const double span = c.num(r, "gpu_e2e_ms");
  return {!e2e ? c.num(r, "trace_ms") : std::isnan(span) ? c.num(r, "e2e_ms") : span};
}

// rays / the sum of the frames' medians (ms), in MRay/s.
double series_mray_s(const std::map<int, FrameTimes>& s) {
  double rays = 0, ms = 0;
  for (const auto& [frame, t] : s) {
    rays += t.rays;
    ms += median_interval(t.times).median;
  }
  return ms > 0 ? rays / ms * 1e-3 : 0.0;
}

void check_speed_file(const TuneOptions& o, const ResultCsv& c, const std::string& option) {
  const ResultKind kind = result_kind(c);
  if (kind != ResultKind::Table && kind != ResultKind::Sweep)
    throw Error(fmt::format("{} {}: not a table or sweep CSV (a tune's <stem>-speed.csv is one)", option, c.path));
  const Experiment e = read_experiment(c);
  const std::string res = fmt::format("{}×{}", o.width, o.height);
  if (e.scenes.size() != 1 || e.tracers.size() != 1 || e.resolutions != std::set<std::string>{res})
    throw Error(
        fmt::format("{} {}: needs one scene, one tracer and --res {}x{}; it holds {} scene(s), {} "
                    "tracer(s), resolution(s) {}",
                    option, c.path, o.width, o.height, e.scenes.size(), e.tracers.size(), join_set(e.resolutions)));
}

}  // namespace

TuneSpeeds read_tune_speeds(const TuneOptions& o, const std::string& path, const std::vector<std::string>& methods,
                            const std::string& option) {
  const ResultCsv c = read_result_csv(path);
  check_speed_file(o, c, option);
  TuneSpeeds s;
  s.source = path;
  s.modeled = !c.rows.empty() && !std::isnan(c.num(c.rows.front(), "modeled_ms"));
  const bool e2e = o.speed.rank == "e2e";
  std::map<std::string, std::map<int, FrameTimes>> trace;
  std::string tracer, tracer_params;
  for (const auto& r : c.rows) {
    const std::string& method = c.get(r, "method");
    if (method == "primary") continue;
    s.scene = c.get(r, "scene");
    s.tracer_label = result_key_of(c, r).label();
    tracer = c.get(r, "tracer"), tracer_params = c.get(r, "tracer_params");
    s.repeats = std::max(s.repeats, static_cast<int>(c.num(r, "repeats")));
    const int frame = static_cast<int>(c.num(r, "frame"));
    const double rays = c.num(r, "rays");
    s.by_method[method].times[frame] = {row_times(c, r, s.modeled, e2e), rays};
    trace[method][frame] = {row_times(c, r, s.modeled, false), rays};
  }
  for (const std::string& m : methods)
    if (!s.by_method.count(m))
      throw Error(fmt::format("{} {}: no rows of {}; measure the same space there (raycoh tune --tracer ...)", option,
                              path, m));
  for (auto& [method, sp] : s.by_method) {
    sp.ranked = series_mray_s(sp.times);
    sp.trace = series_mray_s(trace[method]);
    for (const auto& [frame, t] : sp.times) sp.rays_per_frame += t.rays / static_cast<double>(sp.times.size());
  }
  s.wave_rays = gpu_wave_rays(tracer, tracer_params, path != o.speed.csv, s.wave_basis);
  if (s.wave_rays > 0 && s.wave_basis.empty())
    s.wave_basis = fmt::format("{}: {:.0f} rays resident", s.tracer_label, s.wave_rays);
  return s;
}

TuneSpeeds measure_tune_speeds(const TuneOptions& o, const std::vector<std::string>& methods, uint32_t seed,
                               const std::string& out, const Provenance& provenance) {
  const ExperimentOptions e = speed_options(o, methods, seed, out);
  std::fprintf(stderr, "tune: speed of %zu settings and noopt (%s, seed %u) -> %s\n", methods.size(),
               o.speed.tracer.text().c_str(), seed, e.out.c_str());
  const std::vector<SceneResult> results = run_experiment(e, provenance);
  if (results.empty() || !o.shard.whole()) {
    TuneSpeeds s;
    s.source = e.out;
    return s;
  }
  return read_tune_speeds(o, e.out, methods, "--out");
}

SpeedRatio tune_speed_ratio(const TuneSpeed& base, const TuneSpeed& method) {
  std::vector<FrameTimes> b, m;
  for (const auto& [frame, times] : base.times)
    if (const auto it = method.times.find(frame); it != method.times.end()) {
      b.push_back(times);
      m.push_back(it->second);
    }
  return speed_ratio(b, m);
}

double gpu_wave_rays(const std::string& tracer, const std::string& params, bool measured_here, std::string& basis) {
  basis.clear();
  if (tracer == "simt") return static_cast<double>(simt_resident_rays(params));
#if defined(RAYCOH_HAVE_CUDA)
  if (tracer == "cuda" && measured_here) {
    const long long threads = cuda::device_resident_threads();
    if (threads > 0) basis = fmt::format("{}: {} threads resident at most", cuda::device_name(), threads);
    return static_cast<double>(threads);
  }
#else
  (void)measured_here;
#endif
  return 0;
}

}  // namespace raycoh
