#include "harness/experiment.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <set>

#include "core/error.h"
#include "core/fault_injection.h"
#include "encoders/encoder.h"
#include "encoders/reorder.h"
#include "generators/pixel_order.h"
#include "harness/device_rows.h"
#include "harness/experiment_setup.h"
#include "harness/progress.h"
#include "harness/repeat_timing.h"
#include "pipeline/first_hits.h"
#include "records/record_csv.h"
#include "simt/pipeline_model.h"
#include "simt/timed_replay.h"
#include "tracers/device_pipeline.h"
#include "tracers/tracer.h"

namespace raycoh {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// One run of the loop: the CSV, the rows an interrupted run left, and the sums of the scene being measured.
class ExperimentRun {
 public:
  ExperimentRun(const ExperimentOptions& o, const Provenance& p);
  std::vector<SceneResult> run();

 private:
  std::string unit(size_t si, int frame, size_t mi) const;
  bool owns(size_t si, int frame, size_t mi) const;
  bool owns_any(size_t si, int frame) const;
  void run_scene(size_t si);
  void run_device_primary(int frame);
  void run_device_row(ExperimentRow r, size_t ti, size_t mi);
  void run_frame(int frame);
  void run_methods(int frame, const GBuffer& gbuffer);
  ExperimentRow head(const std::string& pass, size_t mi, size_t ti, int frame) const;
  bool resumed(const ExperimentRow& head, size_t ti);
  bool frame_resumed(int frame);
  template <class Fn>
  Timing measure(size_t ti, Fn&& trace_once);
  void record(ExperimentRow row, size_t ti, double gen_s, const Timing& t, const GenerationStats* gs,
              const ReorderTimings& rt, const ModeledStages& stages);
  void finish_row(ExperimentRow r, size_t ti, const ModeledStages& stages);

  const ExperimentOptions& o_;
  const Provenance& provenance_;
  std::vector<std::unique_ptr<Generator>> generators_;  // one per method
  PermuteMode permute_;
  RecordCsv<ExperimentRow> csv_;
  std::map<std::string, const ExperimentRow*> done_;  // resume key -> resumed row
  std::set<std::string> used_;                        // keys of done_ this run asked for
  std::set<std::string> owned_;                       // --shard: the units this shard measures
  Progress progress_;
  size_t scene_index_ = 0;  // of the scene being measured, for the progress line
  std::unique_ptr<SceneSetup> setup_;
  size_t si_ = 0;  // the scene being measured
  SceneResult res_;
  std::vector<uint32_t> primary_order_, order_;
  std::vector<Hit> hits_;
  RayBatch batch_, sorted_;
  std::string where_;  // the unit and stage being measured, for an error's one line
};

ExperimentRun::ExperimentRun(const ExperimentOptions& o, const Provenance& p)
    : o_(o),
      provenance_(p),
      generators_(checked_generators(o)),
      permute_(parse_permute_mode(o.permute)),
      csv_(o.out, experiment_schema(), CsvWriter::Options::resumable(o.force, experiment_rule(o, generators_, p))) {
  for (const ExperimentRow& row : csv_.resumed()) done_[resume_key(experiment_schema(), row)] = &row;
  if (!o.shard.whole()) {
    std::vector<std::string> units;
    for (size_t si = 0; si < o.scenes.size(); ++si)
      for (int frame = 0; frame < o.frames; ++frame)
        for (size_t mi = 0; mi <= o.methods.size(); ++mi) units.push_back(unit(si, frame, mi));
    const std::vector<int> owner = deal_units(units, o.shard.count);
    for (size_t u = 0; u < units.size(); ++u)
      if (owner[u] == o.shard.index) owned_.insert(units[u]);
  }
  if (!done_.empty())
    std::fprintf(stderr, "resuming: %zu rows already measured in %s\n", done_.size(), csv_.partial_path().c_str());
}

std::vector<SceneResult> ExperimentRun::run() {
  std::vector<SceneResult> results;
  try {
    for (size_t si = 0; si < o_.scenes.size(); ++si) {
      bool any = false;
      for (int frame = 0; frame < o_.frames && !any; ++frame) any = owns_any(si, frame);
      if (!any) continue;  // a shard that owns none of the scene's units does not load it
      run_scene(si);
      results.push_back(std::move(res_));
    }
  } catch (const Error& e) {
    progress_.clear();
    csv_.rethrow_keeping_rows(e, where_);
  }
  if (used_.size() < done_.size()) {
    for (const auto& [key, row] : done_)
      if (!used_.count(key))
        throw Error(fmt::format(
            "--out {}: {} holds {} rows this run did not ask for (e.g. {} {} {} with tracer_params '{}', "
            "encoder_params '{}'); this run's rows are kept beside them; pass --force to replace the file, or choose "
            "another --out",
            o_.out, csv_.partial_path(), done_.size() - used_.size(), row->scene, row->method, row->tracer,
            row->tracer_params, row->encoder_params));
  }
  csv_.finish();
  if (csv_.rows() == 0)
    std::fprintf(stderr, "%s already held every row of this run: nothing was measured\n", o_.out.c_str());
  return results;
}

// Units (records/shard.h): scene x frame x method, and the scene x frame primary pass (mi == methods.size()).
std::string ExperimentRun::unit(size_t si, int frame, size_t mi) const {
  return experiment_unit(scene_name_of(o_.scenes[si]), frame,
                         mi == o_.methods.size() ? "primary" : o_.methods[mi].label);
}

bool ExperimentRun::owns(size_t si, int frame, size_t mi) const {
  return o_.shard.whole() || owned_.count(unit(si, frame, mi));
}

bool ExperimentRun::owns_any(size_t si, int frame) const {
  for (size_t mi = 0; mi <= o_.methods.size(); ++mi)
    if (owns(si, frame, mi)) return true;
  return false;
}

void ExperimentRun::run_scene(size_t si) {
  std::fprintf(stderr, "[%zu/%zu] ", si + 1, o_.scenes.size());
  si_ = si;
  where_ = "scene " + o_.scenes[si] + ", loading it and setting up the tracers";
  res_ = SceneResult{};
  setup_.reset();  // the previous scene's tracers go before the next scene is loaded
  setup_ = std::make_unique<SceneSetup>(o_.scenes[si], o_, generators_, res_.tracer_labels);
  res_.scene = setup_->scene.name;
  res_.triangles = setup_->scene.triangle_count();
  primary_order_ = make_pixel_order(o_.width, o_.height, RayOrder::Tile, kPrimaryTile, kPrimaryTile);
  scene_index_ = si;
  for (int frame = 0; frame < o_.frames; ++frame) run_frame(frame);
  progress_.clear();
}

// The identifying fields of a row: everything known before measuring, the resume key included. mi is a method
// index, or methods.size() for the primary pass.
ExperimentRow ExperimentRun::head(const std::string& pass, size_t mi, size_t ti, int frame) const {
  const bool primary = mi == o_.methods.size();
  const Encoder* enc = primary ? nullptr : setup_->encoders[mi].get();
  ExperimentRow r;
  r.scene = setup_->scene.name;
  r.scene_triangles = setup_->scene.triangle_count();
  r.scene_fingerprint = setup_->fingerprint;
  r.pass = pass;
  r.method = primary ? "primary" : o_.methods[mi].label;
  r.generator = primary ? "primary" : o_.methods[mi].generator.name;
  r.generator_params = primary ? kPrimaryParams : generators_[mi]->params();
  r.tracer = o_.tracers[ti].name;
  r.tracer_params = setup_->tracers[ti]->params();
  r.bvh = setup_->tracers[ti]->bvh_layout();
  r.width = o_.width;
  r.height = o_.height;
  r.frame = frame;
  r.seed = o_.seed;
  r.repeats = setup_->repeats[ti];
  r.encoder = enc ? enc->name() : "";
  r.encoder_params = enc ? enc->params() : "";
  // Reorderings record how they were applied; `none` and the primary pass have nothing to apply.
  r.permute = enc && enc->key_bits() > 0 ? o_.permute : "";
  r.provenance = provenance_;
  r.provenance.device = device_of(o_.tracers[ti]);
  r.gpu = setup_->gpu[ti];
  read_gpu_clocks(r.gpu, true);
  set_recorded_params(r);
  return r;
}

// Rows already measured by an interrupted run count as measured now.
bool ExperimentRun::resumed(const ExperimentRow& head, size_t ti) {
  const auto it = done_.find(resume_key(experiment_schema(), head));
  if (it == done_.end()) return false;
  used_.insert(it->first);
  accumulate(*it->second, res_.tracer_labels[ti], ti == 0, o_.frames, res_);
  return true;
}

// A frame whose every row (of this shard) was measured is taken as it is, without tracing its primary rays again.
bool ExperimentRun::frame_resumed(int frame) {
  const size_t primary = o_.methods.size();
  for (size_t ti = 0; ti < o_.tracers.size(); ++ti)
    for (size_t mi = 0; mi <= primary; ++mi)
      if (owns(si_, frame, mi) &&
          !done_.count(resume_key(experiment_schema(), head(mi == primary ? "primary" : "secondary", mi, ti, frame))))
        return false;
  for (size_t ti = 0; ti < o_.tracers.size(); ++ti) {
    if (owns(si_, frame, primary)) resumed(head("primary", primary, ti, frame), ti);
    for (size_t mi = 0; mi < primary; ++mi)
      if (owns(si_, frame, mi)) resumed(head("secondary", mi, ti, frame), ti);
  }
  return true;
}

// Timing tracers get one untimed warm-up per scene, then the median of `repeats` calls. Modelling tracers
// (counters, deterministic) run once: their wall time is the model's, not a GPU's.
template <class Fn>
Timing ExperimentRun::measure(size_t ti, Fn&& trace_once) {
  Tracer& tracer = *setup_->tracers[ti];
  if (inject_fault("trace")) throw DeviceFault("injected device fault (RAYCOH_INJECT_FAULT=trace:N)");
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

void ExperimentRun::record(ExperimentRow r, size_t ti, double gen_s, const Timing& t, const GenerationStats* gs,
                           const ReorderTimings& rt, const ModeledStages& stages) {
  r.gen_ms = gen_s * 1e3;
  if (gs) set_generation(r, *gs);
  r.key_ms = rt.key_ms;
  r.sort_ms = rt.sort_ms;
  r.permute_ms = rt.permute_ms;
  set_host_times(r, t, r.gen_ms + rt.total_ms());
  finish_row(std::move(r), ti, stages);
}

// The counters and model of counting tracers, then the row is written and summed.
void ExperimentRun::finish_row(ExperimentRow r, size_t ti, const ModeledStages& stages) {
  if (const CoherenceCounters* c = setup_->tracers[ti]->last_counters()) set_counters(r, *c, stages);
  read_gpu_clocks(r.gpu, false);
  csv_.write(r);
  accumulate(r, res_.tracer_labels[ti], ti == 0, o_.frames, res_);
}

void ExperimentRun::run_frame(int frame) {
  if (!owns_any(si_, frame) || frame_resumed(frame)) return;
  const FirstHits first = first_hits(setup_->scene, *setup_->gbuffer_tracer, o_.width, o_.height, primary_order_,
                                     o_.seed, static_cast<uint32_t>(frame), true);
  // A frame without a single hit would measure 0 secondary rays: a table of zeros is no result.
  if (first.gbuffer.hits == 0)
    throw Error(
        fmt::format("scene '{}': the camera sees no triangle ({} of {} camera rays hit at {}x{}); nothing "
                    "to measure",
                    setup_->scene.source, 0, first.primary.rays.size(), o_.width, o_.height));
  const std::vector<Ray>& rays = first.primary.rays;
  hits_.resize(rays.size());
  for (size_t ti = 0; ti < o_.tracers.size() && owns(si_, frame, o_.methods.size()); ++ti) {  // the coherent bound
    ExperimentRow r = head("primary", o_.methods.size(), ti, frame);
    if (setup_->pipelines[ti] || resumed(r, ti)) continue;  // device pipelines: run_device_primary
    where_ = fmt::format("scene {}, frame {}, primary pass, tracer {}, trace", res_.scene, frame, r.tracer);
    const Timing t = measure(ti, [&] { setup_->tracers[ti]->trace(rays.data(), rays.size(), hits_.data()); });
    r.rays = rays.size();
    record(std::move(r), ti, 0.0, t, nullptr, ReorderTimings{}, ModeledStages{});
  }
  run_device_primary(frame);
  run_methods(frame, first.gbuffer);
}

// Methods sharing a generator share its batch within a frame (generated once, timed once).
void ExperimentRun::run_methods(int frame, const GBuffer& gbuffer) {
  std::string batch_of;
  double gen_s = 0.0;
  GenerationStats gs;
  const size_t methods = o_.methods.size();
  for (size_t mi = 0; mi < methods; ++mi) {
    if (!owns(si_, frame, mi)) continue;
    progress_.update(scene_index_, o_.scenes.size(), static_cast<int>(size_t(frame) * methods + mi),
                     static_cast<int>(size_t(o_.frames) * methods),
                     fmt::format("{} frame {}/{} {}", res_.scene, frame + 1, o_.frames, o_.methods[mi].label));
    const std::string unit = fmt::format("scene {}, frame {}, method {}", res_.scene, frame, o_.methods[mi].label);
    std::vector<std::pair<size_t, ExperimentRow>> todo;  // host-pipeline tracer index, row head
    for (size_t ti = 0; ti < o_.tracers.size(); ++ti)
      if (ExperimentRow r = head("secondary", mi, ti, frame); !resumed(r, ti)) {
        where_ = fmt::format("{}, tracer {}, device pass", unit, r.tracer);
        if (setup_->pipelines[ti])
          run_device_row(std::move(r), ti, mi);
        else
          todo.emplace_back(ti, std::move(r));
      }
    if (todo.empty()) continue;
    const std::string gen_key = o_.methods[mi].generator.name + ":" + generators_[mi]->params();
    if (gen_key != batch_of) {
      where_ = unit + ", generation";
      const auto t_gen = Clock::now();
      generators_[mi]->generate(setup_->scene, gbuffer, o_.seed, batch_, gs);
      gen_s = seconds_since(t_gen);
      batch_of = gen_key;
    }
    ReorderTimings rt;
    where_ = unit + ", reordering";
    const bool reordered = reorder(*setup_->encoders[mi], batch_, permute_, sorted_, order_, rt);
    const bool indirect = reordered && permute_ == PermuteMode::Indirect;
    const std::vector<Ray>& rays = reordered && !indirect ? sorted_.rays : batch_.rays;
    hits_.resize(batch_.size());
    for (auto& [ti, r] : todo) {
      Tracer& tracer = *setup_->tracers[ti];
      where_ = fmt::format("{}, tracer {}, trace", unit, r.tracer);
      const Timing t = measure(ti, [&] {
        if (indirect)
          tracer.trace_indirect(rays.data(), order_.data(), rays.size(), hits_.data());
        else
          tracer.trace(rays.data(), rays.size(), hits_.data());
      });
      r.rays = batch_.size();
      const GpuModelConfig* gpu = tracer.gpu_model();
      const Encoder& enc = *setup_->encoders[mi];
      record(std::move(r), ti, gen_s, t, &gs, rt,
             gpu ? modeled_stages(*gpu, size_t(o_.width) * size_t(o_.height), enc.key_bits(), enc.window(),
                                  permute_ == PermuteMode::Physical, batch_.size(), order_)
                 : ModeledStages{});
    }
  }
}

// Device pipelines: camera rays made and traced on the device (the primary row), their G-buffer uploaded.
void ExperimentRun::run_device_primary(int frame) {
  const auto f = static_cast<uint32_t>(frame);
  for (size_t ti = 0; ti < o_.tracers.size(); ++ti) {
    DevicePipeline* p = setup_->pipelines[ti];
    if (!p) continue;
    auto pass = [&] { return p->primary(o_.width, o_.height, kPrimaryTile, kPrimaryTile, o_.seed, f, true); };
    ExperimentRow r = head("primary", o_.methods.size(), ti, frame);
    where_ = fmt::format("scene {}, frame {}, primary pass, tracer {}, device pass", res_.scene, frame, r.tracer);
    if (owns(si_, frame, o_.methods.size()) && !resumed(r, ti)) {
      r.rays = size_t(o_.width) * size_t(o_.height);
      set_device_times(r, measure_device(pass, setup_->repeats[ti], setup_->models[ti]), setup_->models[ti]);
      finish_row(std::move(r), ti, ModeledStages{});
    } else {
      pass();
    }
    p->upload_first_hits();
  }
}

void ExperimentRun::run_device_row(ExperimentRow r, size_t ti, size_t mi) {
  GenerationStats gs;
  DevicePipeline& p = *setup_->pipelines[ti];
  auto pass = [&] {
    if (inject_fault("trace")) throw DeviceFault("injected device fault (RAYCOH_INJECT_FAULT=trace:N)");
    return p.secondary(*generators_[mi], *setup_->encoders[mi], permute_, o_.seed, gs);
  };
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
