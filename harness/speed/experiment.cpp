#include "harness/speed/experiment.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

#include "core/error.h"
#include "core/fault_injection.h"
#include "encoders/encoder.h"
#include "encoders/reorder.h"
#include "generators/pixel_order.h"
#include "harness/common/progress.h"
#include "harness/speed/device_rows.h"
#include "harness/speed/experiment_setup.h"
#include "harness/speed/experiment_units.h"
#include "harness/speed/repeat_timing.h"
#include "pipeline/first_hits.h"
#include "records/hw_columns.h"
#include "records/record_csv.h"
#include "simt/pipeline_model.h"
#include "simt/stage_model.h"
#include "simt/timed_replay.h"
#include "tracers/device_pipeline.h"
#include "tracers/tracer.h"

namespace raycoh {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Just before a row is measured: the experiment loop's site of injected faults (core/fault_injection.h, `trace`:
// a device fault where there may be no device) and the GPU's clocks at the start (GPU rows only).
void begin_measurement(ExperimentRow& r) {
  if (inject_fault("trace")) throw DeviceFault("injected device fault (RAYCOH_INJECT_FAULT=trace:N)");
  read_gpu_clocks(r.gpu, true);
}

// One run of the loop, as steps: run() takes the scenes in turn (run_scene: load, set up the tracers), run_scene
// the frames (run_frame: first hits, then the passes), run_frame the primary pass (run_primary; run_device_primary
// for device pipelines) and then each method's secondary pass (run_methods -> run_method: generate, reorder,
// trace; run_device_row for device pipelines). Which units this shard owns and which rows an interrupted run left
// are ExperimentUnits' (harness/speed/experiment_units.h); timing is repeat_timing.h's (host) and device_rows.h's
// (device pipelines). A row is made in three steps: head() (what is known before measuring, the resume key),
// record() (the times), finish_row() (the counters; written, summed into the scene's result).
class ExperimentRun {
 public:
  ExperimentRun(const ExperimentOptions& o, const Provenance& p);
  std::vector<SceneResult> run();

 private:
  // The batches and their buffers, reused from frame to frame.
  struct Buffers {
    std::vector<uint32_t> primary_order;  // the primary pass's pixel order (8x8 tiles)
    std::vector<uint32_t> order;          // a reordering's permutation of the batch
    std::vector<Hit> hits;
    RayBatch batch, sorted;  // a method's batch, and its reordered copy (physical permute)
  };
  // The batch of the last generation in a frame: methods sharing a generator share it (generated and timed once
  // per host repeat).
  struct Generated {
    std::string of;              // "generator:params", empty before the first
    std::vector<double> gen_ms;  // each repeat's generation time
    GenerationStats stats;
  };

  void check_all_resumed_rows_asked_for() const;
  void run_scene(size_t si);
  void run_frame(int frame);
  void run_primary(int frame, const std::vector<Ray>& rays);
  void run_device_primary(int frame);
  void run_methods(int frame, const GBuffer& gbuffer);
  void run_method(const Unit& u, const GBuffer& gbuffer, Generated& generated);
  void run_device_row(ExperimentRow r, size_t ti, size_t mi);
  ExperimentRow head(const Unit& u, size_t ti) const;
  bool resumed(const ExperimentRow& head);
  bool frame_resumed(int frame);
  template <class Fn>
  Timing measure(size_t ti, Fn&& trace_once);
  size_t host_repeats(const std::vector<std::pair<size_t, ExperimentRow>>& todo) const;
  void record(ExperimentRow row, size_t ti, const StageSamples& stages, const Timing& t, const GenerationStats* gs,
              const ModeledStages& modeled);
  void finish_row(ExperimentRow r, size_t ti, const ModeledStages& stages);

  const ExperimentOptions& o_;
  const Provenance& provenance_;
  std::vector<std::unique_ptr<Generator>> generators_;  // one per method
  PermuteMode permute_;
  RecordCsv<ExperimentRow> csv_;
  ExperimentUnits units_;  // shard ownership and resumed rows
  Progress progress_;
  std::unique_ptr<SceneSetup> setup_;
  size_t si_ = 0;    // the scene being measured
  SceneResult res_;  // its sums
  Buffers buffers_;
  std::string where_;  // the unit and stage being measured, for an error's one line
};

ExperimentRun::ExperimentRun(const ExperimentOptions& o, const Provenance& p)
    : o_(o),
      provenance_(p),
      generators_(checked_generators(o)),
      permute_(parse_permute_mode(o.permute)),
      csv_(o.out, experiment_schema(), CsvWriter::Options::resumable(o.force, experiment_rule(o, generators_, p))),
      units_(o, csv_.resumed()) {
  buffers_.primary_order = make_pixel_order(o.width, o.height, RayOrder::Tile, kPrimaryTile, kPrimaryTile);
  if (units_.resumed_rows() > 0)
    std::fprintf(stderr, "resuming: %zu rows already measured in %s\n", units_.resumed_rows(),
                 csv_.partial_path().c_str());
}

std::vector<SceneResult> ExperimentRun::run() {
  std::vector<SceneResult> results;
  try {
    for (size_t si = 0; si < o_.scenes.size(); ++si) {
      if (!units_.owns_any(si)) continue;  // a shard that owns none of the scene's units does not load it
      run_scene(si);
      results.push_back(std::move(res_));
    }
  } catch (const Error& e) {
    progress_.clear();
    csv_.rethrow_keeping_rows(e, where_);
  }
  check_all_resumed_rows_asked_for();
  csv_.finish();
  if (csv_.rows() == 0)
    std::fprintf(stderr, "%s already held every row of this run: nothing was measured\n", o_.out.c_str());
  return results;
}

// Resumed rows this run did not ask for differ in what is known only once a scene is loaded (experiment_rule).
void ExperimentRun::check_all_resumed_rows_asked_for() const {
  const ExperimentRow* row = units_.first_untaken();
  if (!row) return;
  throw Error(fmt::format(
      "--out {}: {} holds {} rows this run did not ask for (e.g. {} {} {} with tracer_params '{}', "
      "encoder_params '{}'); this run's rows are kept beside them; pass --force to replace the file, or choose "
      "another --out",
      o_.out, csv_.partial_path(), units_.untaken_rows(), row->scene, row->method, row->tracer, row->tracer_params,
      row->encoder_params));
}

void ExperimentRun::run_scene(size_t si) {
  std::fprintf(stderr, "[%zu/%zu] ", si + 1, o_.scenes.size());
  si_ = si;
  where_ = "scene " + o_.scenes[si] + ", loading it and setting up the tracers";
  res_ = SceneResult{};
  setup_.reset();  // the previous scene's tracers go before the next scene is loaded
  setup_ = std::make_unique<SceneSetup>(o_.scenes[si], o_, generators_, res_.tracers);
  res_.scene = setup_->scene.name;
  res_.triangles = setup_->scene.triangle_count();
  for (int frame = 0; frame < o_.frames; ++frame) run_frame(frame);
  progress_.clear();
}

// The identifying fields of a row: everything known before measuring, the resume key included.
ExperimentRow ExperimentRun::head(const Unit& u, size_t ti) const {
  return unit_head(o_, *setup_, provenance_, generators_, u, ti);
}

// Rows already measured by an interrupted run count as measured now.
bool ExperimentRun::resumed(const ExperimentRow& head) {
  const ExperimentRow* row = units_.take(head);
  if (!row) return false;
  accumulate(*row, o_.frames, res_);
  return true;
}

// A frame whose every row (of this shard) was measured is taken as it is, without tracing its primary rays again.
bool ExperimentRun::frame_resumed(int frame) {
  std::vector<Unit> owned;
  for (const Unit& u : frame_units(o_, si_, frame))
    if (units_.owns(u)) owned.push_back(u);
  for (size_t ti = 0; ti < o_.tracers.size(); ++ti)
    for (const Unit& u : owned)
      if (!units_.done(head(u, ti))) return false;
  for (size_t ti = 0; ti < o_.tracers.size(); ++ti)
    for (const Unit& u : owned) resumed(head(u, ti));
  return true;
}

// Timing tracers get one untimed warm-up per scene, then the median of `repeats` calls. Modelling tracers
// (counters, deterministic) run once: their wall time is the model's, not a GPU's.
template <class Fn>
Timing ExperimentRun::measure(size_t ti, Fn&& trace_once) {
  Tracer& tracer = *setup_->tracers[ti];
  auto wall = [&] {
    const auto t0 = Clock::now();
    trace_once();
    return seconds_since(t0);
  };
  if (setup_->models[ti]) return time_repeats(wall, 1);
  if (!setup_->warmed[ti]) trace_once();
  setup_->warmed[ti] = true;
  // A device tracer reports its kernel time (CUDA events, no transfers): that is the trace time.
  auto device = [&] {
    trace_once();
    return tracer.last_device_ms() * 1e-3;
  };
  if (tracer.last_device_ms() >= 0.0) return time_repeats(device, setup_->repeats[ti]);
  return time_repeats(wall, setup_->repeats[ti]);
}

void ExperimentRun::record(ExperimentRow r, size_t ti, const StageSamples& stages, const Timing& t,
                           const GenerationStats* gs, const ModeledStages& modeled) {
  if (gs) set_generation(r, *gs);
  set_host_times(r, t, stages);
  finish_row(std::move(r), ti, modeled);
}

// How often a method's generation and reordering are timed: the most repeats any of its host tracers traces
// (models and simulators run once), so each repeat's end to end holds its own generation and sorting.
size_t ExperimentRun::host_repeats(const std::vector<std::pair<size_t, ExperimentRow>>& todo) const {
  size_t n = 1;
  for (const auto& [ti, r] : todo)
    if (!setup_->models[ti]) n = std::max(n, static_cast<size_t>(std::max(1, setup_->repeats[ti])));
  return n;
}

// The counters and model of counting tracers, then the row is written and summed.
void ExperimentRun::finish_row(ExperimentRow r, size_t ti, const ModeledStages& stages) {
  if (const CoherenceCounters* c = setup_->tracers[ti]->last_counters()) set_counters(r, *c, stages);
  if (const HwCounters* h = last_hw_counters(*setup_->tracers[ti])) set_hw_counters(r, *h);
  read_gpu_clocks(r.gpu, false);
  csv_.write(r);
  accumulate(r, o_.frames, res_);
}

void ExperimentRun::run_frame(int frame) {
  if (!units_.owns_any(si_, frame) || frame_resumed(frame)) return;
  const FirstHits first = first_hits(setup_->scene, *setup_->gbuffer_tracer, o_.width, o_.height,
                                     buffers_.primary_order, o_.seed, static_cast<uint32_t>(frame), true);
  // A frame without a single hit would measure 0 secondary rays: a table of zeros is no result.
  if (first.gbuffer.hits == 0)
    throw Error(
        fmt::format("scene '{}': the camera sees no triangle ({} of {} camera rays hit at {}x{}); nothing "
                    "to measure",
                    setup_->scene.source, 0, first.primary.rays.size(), o_.width, o_.height));
  run_primary(frame, first.primary.rays);
  run_device_primary(frame);
  run_methods(frame, first.gbuffer);
}

// The primary pass of host-pipeline tracers: the camera rays, the coherent bound.
void ExperimentRun::run_primary(int frame, const std::vector<Ray>& rays) {
  buffers_.hits.resize(rays.size());
  const Unit u{si_, frame, Pass::Primary, 0};
  if (!units_.owns(u)) return;
  for (size_t ti = 0; ti < o_.tracers.size(); ++ti) {
    ExperimentRow r = head(u, ti);
    if (setup_->pipelines[ti] || resumed(r)) continue;  // device pipelines: run_device_primary
    where_ = fmt::format("scene {}, frame {}, primary pass, tracer {}, trace", res_.scene, frame, r.tracer);
    begin_measurement(r);
    const Timing t = measure(ti, [&] { setup_->tracers[ti]->trace(rays.data(), rays.size(), buffers_.hits.data()); });
    r.rays = rays.size();
    record(std::move(r), ti, StageSamples{}, t, nullptr, ModeledStages{});
  }
}

void ExperimentRun::run_methods(int frame, const GBuffer& gbuffer) {
  Generated generated;
  const size_t methods = o_.methods.size();
  for (const Unit& u : frame_units(o_, si_, frame)) {
    if (u.primary() || !units_.owns(u)) continue;
    progress_.update(si_, o_.scenes.size(), static_cast<int>(size_t(frame) * methods + u.method),
                     static_cast<int>(size_t(o_.frames) * methods),
                     fmt::format("{} frame {}/{} {}", res_.scene, frame + 1, o_.frames, o_.methods[u.method].label));
    run_method(u, gbuffer, generated);
  }
}

// One method's secondary pass: device pipelines run it whole (run_device_row); for the others its batch is
// generated (or the previous method's reused), reordered and traced by each.
void ExperimentRun::run_method(const Unit& u, const GBuffer& gbuffer, Generated& generated) {
  const size_t mi = u.method;
  const std::string unit = fmt::format("scene {}, frame {}, method {}", res_.scene, u.frame, o_.methods[mi].label);
  std::vector<std::pair<size_t, ExperimentRow>> todo;  // host-pipeline tracer index, row head
  for (size_t ti = 0; ti < o_.tracers.size(); ++ti)
    if (ExperimentRow r = head(u, ti); !resumed(r)) {
      where_ = fmt::format("{}, tracer {}, device pass", unit, r.tracer);
      if (setup_->pipelines[ti])
        run_device_row(std::move(r), ti, mi);
      else
        todo.emplace_back(ti, std::move(r));
    }
  if (todo.empty()) return;
  Buffers& b = buffers_;
  const size_t repeats = host_repeats(todo);
  const std::string gen_key = o_.methods[mi].generator.name + ":" + generators_[mi]->params();
  if (gen_key != generated.of || generated.gen_ms.size() < repeats) {
    where_ = unit + ", generation";
    generated.gen_ms =
        time_generation(*generators_[mi], setup_->scene, gbuffer, o_.seed, b.batch, generated.stats, repeats);
    generated.of = gen_key;
  }
  StageSamples stages;
  stages.gen_ms.assign(generated.gen_ms.begin(), generated.gen_ms.begin() + static_cast<std::ptrdiff_t>(repeats));
  where_ = unit + ", reordering";
  Encoder& enc = *setup_->encoders[mi];
  const bool reordered = time_reordering(enc, b.batch, permute_, b.sorted, b.order, repeats, stages);
  const bool indirect = reordered && permute_ == PermuteMode::Indirect;
  const std::vector<Ray>& rays = reordered && !indirect ? b.sorted.rays : b.batch.rays;
  b.hits.resize(b.batch.size());
  for (auto& [ti, r] : todo) {
    Tracer& tracer = *setup_->tracers[ti];
    where_ = fmt::format("{}, tracer {}, trace", unit, r.tracer);
    begin_measurement(r);
    const Timing t = measure(ti, [&] {
      if (indirect)
        tracer.trace_indirect(rays.data(), b.order.data(), rays.size(), b.hits.data());
      else
        tracer.trace(rays.data(), rays.size(), b.hits.data());
    });
    r.rays = b.batch.size();
    const GpuModelConfig* gpu = tracer.gpu_model();
    record(std::move(r), ti, stages, t, &generated.stats,
           gpu ? stage_model(*gpu,
                             stage_work(*generators_[mi], enc, permute_ == PermuteMode::Physical, o_.width, o_.height,
                                        b.batch.size(), &generated.stats),
                             b.order)
               : ModeledStages{});
  }
}

// Device pipelines: camera rays made and traced on the device (the primary row), their G-buffer made there.
void ExperimentRun::run_device_primary(int frame) {
  const auto f = static_cast<uint32_t>(frame);
  const Unit u{si_, frame, Pass::Primary, 0};
  for (size_t ti = 0; ti < o_.tracers.size(); ++ti) {
    DevicePipeline* p = setup_->pipelines[ti];
    if (!p) continue;
    auto pass = [&] { return p->primary(o_.width, o_.height, kPrimaryTile, kPrimaryTile, o_.seed, f, true); };
    ExperimentRow r = head(u, ti);
    where_ = fmt::format("scene {}, frame {}, primary pass, tracer {}, device pass", res_.scene, frame, r.tracer);
    if (units_.owns(u) && !resumed(r)) {
      r.rays = size_t(o_.width) * size_t(o_.height);
      begin_measurement(r);
      set_device_times(r, measure_device(pass, setup_->repeats[ti], setup_->models[ti]), setup_->models[ti]);
      finish_row(std::move(r), ti, ModeledStages{});
    } else {
      pass();
    }
    p->first_hits_gbuffer();
  }
}

void ExperimentRun::run_device_row(ExperimentRow r, size_t ti, size_t mi) {
  GenerationStats gs;
  DevicePipeline& p = *setup_->pipelines[ti];
  auto pass = [&] { return p.secondary(*generators_[mi], *setup_->encoders[mi], permute_, o_.seed, gs); };
  begin_measurement(r);
  const DeviceMeasurement m = measure_device(pass, setup_->repeats[ti], setup_->models[ti]);
  r.rays = gs.rays;
  set_device_times(r, m, setup_->models[ti]);
  set_generation(r, gs);
  set_stage_traffic(r, p, *setup_->encoders[mi], permute_, size_t(o_.width) * size_t(o_.height), m.median.fused);
  finish_row(std::move(r), ti, ModeledStages{});
}

}  // namespace

std::vector<SceneResult> run_experiment(const ExperimentOptions& options, const Provenance& provenance) {
  return ExperimentRun(options, provenance).run();
}

}  // namespace raycoh
