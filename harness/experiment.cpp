#include "harness/experiment.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <set>

#include "bvh/bvh_build.h"
#include "core/durable_file.h"
#include "core/error.h"
#include "encoders/encoder.h"
#include "encoders/reorder.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "generators/primary.h"
#include "harness/memory_check.h"
#include "harness/progress.h"
#include "harness/record_csv.h"
#include "shading/reference.h"
#include "simt/pipeline_model.h"
#include "simt/timed_replay.h"
#include "tracers/tracer.h"

namespace raycoh {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The primary pass uses the compact 8x8 tile order every generator uses by default.
constexpr int kPrimaryTile = 8;
const char* const kPrimaryParams = "order=tile,tile=8x8";

struct Timing {
  double median = 0, min = 0;
};

// Times `repeats` calls of fn (fn returns its own time in seconds); reports the median and the fastest.
template <class Fn>
Timing time_repeats(Fn&& fn, int repeats) {
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r) t.push_back(fn());
  std::sort(t.begin(), t.end());
  return {t[t.size() / 2], t.front()};
}

// Two scene specs of one name would write rows with the same key ("cornell" and "cornell:size=2").
void check_scene_names(const std::vector<std::string>& specs) {
  std::map<std::string, std::string> seen;
  for (const std::string& spec : specs) {
    const auto [it, fresh] = seen.emplace(scene_name_of(spec), spec);
    if (!fresh)
      throw Error(
          fmt::format("--scenes: {} and {} are both named '{}' in the CSV's scene column; run them with "
                      "separate --out files",
                      it->second, spec, it->first));
  }
}

void check_options(const ExperimentOptions& o) {
  if (o.width < 1 || o.width > 16384 || o.height < 1 || o.height > 16384)
    throw Error(fmt::format("--res {}x{}: width and height must be in [1, 16384]", o.width, o.height));
  if (o.frames < 1 || o.frames > 100000) throw Error(fmt::format("--frames {}: must be in [1, 100000]", o.frames));
  if (o.repeats < 1 || o.repeats > 1000) throw Error(fmt::format("--repeat {}: must be in [1, 1000]", o.repeats));
  if (o.shard.count < 1 || o.shard.count > kMaxShards || o.shard.index < 0 || o.shard.index >= o.shard.count)
    throw Error(fmt::format("--shard {}: expected I/N with N in [1, {}] and I in [0, N)", o.shard.text(), kMaxShards));
  if (o.scenes.empty()) throw Error("--scenes: empty list");
  if (o.tracers.empty()) throw Error("--tracers: empty list");
  RAYCOH_CHECK(std::any_of(o.methods.begin(), o.methods.end(), [](const Method& m) { return m.label == "noopt"; }),
               "the methods must contain the noopt baseline");
  for (const std::string& spec : o.scenes) check_scene_spec("--scenes", spec);
  check_scene_names(o.scenes);
  check_output_file("--out", o.out);
  check_memory(fmt::format("--res {}x{}", o.width, o.height), experiment_bytes(o.width, o.height));
}

// Every name and parameter is checked before anything is measured.
std::vector<std::unique_ptr<Generator>> checked_generators(const ExperimentOptions& o) {
  check_options(o);
  std::vector<std::unique_ptr<Generator>> generators;
  for (const Method& m : o.methods) generators.push_back(make_generator(m.generator));
  return generators;
}

// The scene column's fingerprint (shading/reference.h): built-in scenes by their spec, files by their bytes and
// the files beside them. A file spec with a ":sun=..." suffix is the file's fingerprint plus the suffix.
std::string experiment_fingerprint(const std::string& spec) {
  std::error_code ec;
  const size_t colon = spec.rfind(':');
  if (!std::filesystem::exists(spec, ec) && colon != std::string::npos && colon > 0 &&
      std::filesystem::exists(spec.substr(0, colon), ec))
    return scene_fingerprint(spec.substr(0, colon)) + spec.substr(colon);
  return scene_fingerprint(spec);
}

// One scene with its BVH, tracers and encoders; tracers keep references to scene and BVH, so it never moves.
struct SceneSetup {
  std::string fingerprint;
  Scene scene;
  Bvh bvh;
  std::vector<std::unique_ptr<Tracer>> tracers;
  std::vector<std::unique_ptr<Encoder>> encoders;  // one per method
  std::unique_ptr<Tracer> gbuffer_tracer;
  std::vector<bool> warmed, models;  // models: tracers with coherence counters (deterministic, run once)
  SceneSetup(const std::string& spec, const ExperimentOptions& o, std::vector<std::string>& labels);
  SceneSetup(const SceneSetup&) = delete;
  SceneSetup& operator=(const SceneSetup&) = delete;
};

SceneSetup::SceneSetup(const std::string& spec, const ExperimentOptions& o, std::vector<std::string>& labels) {
  const auto t_load = Clock::now();
  fingerprint = experiment_fingerprint(spec);
  scene = load_scene(spec);
  const double load_s = seconds_since(t_load);
  bvh = build_bvh(scene);
  std::fprintf(stderr,
               "%s: %zu triangles, loaded in %.2f s; BVH %zu inner nodes, %zu leaves, depth %zu, SAH %.1f, %.1f MiB, "
               "built in %.2f s\n",
               scene.name.c_str(), scene.triangle_count(), load_s, bvh.stats.inner_nodes, bvh.stats.leaves,
               bvh.stats.max_depth, bvh.stats.sah_cost, bvh.stats.bytes / 1048576.0, bvh.stats.build_seconds);
  for (const std::string& s : analyse(scene).skipped_stages) std::fprintf(stderr, "    skipped: %s\n", s.c_str());
  for (const std::string& s : scene.load_notes) std::fprintf(stderr, "    loader: %s\n", s.c_str());
  for (const PluginSpec& t : o.tracers) {
    tracers.push_back(make_tracer(t, scene, bvh));
    const std::string p = tracers.back()->params();
    labels.push_back(p.empty() ? t.name : t.name + "[" + p + "]");
    models.push_back(tracers.back()->last_counters() != nullptr);
  }
  warmed.assign(tracers.size(), false);
  for (const Method& m : o.methods) encoders.push_back(make_encoder(m.encoder, EncoderContext{scene.bounds, &bvh}));
  gbuffer_tracer = make_tracer({"cpu", ""}, scene, bvh);
}

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
  void run_frame(int frame);
  void run_methods(int frame, const GBuffer& gbuffer);
  ExperimentRow head(const std::string& pass, size_t mi, size_t ti, int frame) const;
  bool resumed(const ExperimentRow& head, size_t ti);
  bool frame_resumed(int frame);
  template <class Fn>
  Timing measure(size_t ti, Fn&& trace_once);
  ModeledStages model_stages(const GpuModelConfig& gpu, size_t mi, bool reordered) const;
  void record(ExperimentRow row, size_t ti, double gen_s, const Timing& t, const GenerationStats* gs,
              const ReorderTimings& rt, const ModeledStages& stages);

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
};

// What rows of an earlier run must hold to be this run's (harness/csv.h): everything known before a scene is
// loaded. Tracer and encoder parameters are known only then; rows differing there are found at the end (run()).
ResumeRule experiment_rule(const ExperimentOptions& o, const std::vector<std::unique_ptr<Generator>>& generators,
                           const Provenance& p) {
  std::set<std::string> scenes, methods = {"primary"}, params = {kPrimaryParams}, tracers, frames;
  for (const std::string& spec : o.scenes) scenes.insert(scene_name_of(spec));
  for (size_t mi = 0; mi < o.methods.size(); ++mi) {
    methods.insert(o.methods[mi].label);
    params.insert(generators[mi]->params());
  }
  for (const PluginSpec& t : o.tracers) tracers.insert(t.name);
  for (int f = 0; f < o.frames; ++f) frames.insert(std::to_string(f));
  ResumeRule rule;
  rule.require("scene", scenes)
      .require("pass", {"primary", "secondary"})
      .require("method", methods)
      .require("generator_params", params)
      .require("tracer", tracers)
      .require("width", {std::to_string(o.width)})
      .require("height", {std::to_string(o.height)})
      .require("frame", frames)
      .require("seed", {std::to_string(o.seed)})
      .require("repeats", {std::to_string(o.repeats), "1"})  // counting tracers run once
      .require("permute", {o.permute, ""});
  return require_provenance(rule, p);
}

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
    csv_.rethrow_keeping_rows(e);
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

// Units (harness/shard.h): scene x frame x method, and the scene x frame primary pass (mi == methods.size()).
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
  res_ = SceneResult{};
  setup_.reset();  // the previous scene's tracers go before the next scene is loaded
  setup_ = std::make_unique<SceneSetup>(o_.scenes[si], o_, res_.tracer_labels);
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
  r.width = o_.width;
  r.height = o_.height;
  r.frame = frame;
  r.seed = o_.seed;
  r.repeats = setup_->models[ti] ? 1 : o_.repeats;
  r.encoder = enc ? enc->name() : "";
  r.encoder_params = enc ? enc->params() : "";
  // Reorderings record how they were applied; `none` and the primary pass have nothing to apply.
  r.permute = enc && enc->key_bits() > 0 ? o_.permute : "";
  r.provenance = provenance_;
  r.provenance.device = device_of(o_.tracers[ti]);
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
  if (tracer.last_device_ms() >= 0.0) return time_repeats(device, o_.repeats);
  return time_repeats(wall, o_.repeats);
}

// The stages around the trace on a modelling tracer's GPU (simt/pipeline_model.h): generation of the batch,
// and for a reordering its keys, sort and (physical mode) permutation. Indirect mode has no permutation kernel;
// the modeled trace then reads the rays in sorted order as if gathered (docs/simt-model.md, section 3).
ModeledStages ExperimentRun::model_stages(const GpuModelConfig& gpu, size_t mi, bool reordered) const {
  ModeledStages m;
  m.gen_ms = modeled_generation_ms(gpu, size_t(o_.width) * size_t(o_.height), batch_.size());
  if (!reordered) return m;
  if (setup_->encoders[mi]->window() > 0) {  // one on-chip binning kernel: no key, sort or permutation pass
    m.sort_ms = modeled_window_ms(gpu, batch_.size(), permute_ == PermuteMode::Physical);
    return m;
  }
  const int bits = setup_->encoders[mi]->key_bits();
  m.key_ms = modeled_key_ms(gpu, batch_.size(), bits);
  m.sort_ms = modeled_sort_ms(gpu, batch_.size(), bits);
  if (permute_ == PermuteMode::Physical) m.permute_ms = modeled_permute_ms(gpu, order_.data(), order_.size());
  return m;
}

void ExperimentRun::record(ExperimentRow r, size_t ti, double gen_s, const Timing& t, const GenerationStats* gs,
                           const ReorderTimings& rt, const ModeledStages& stages) {
  const double rays = static_cast<double>(r.rays);
  const double e2e_s = gen_s + rt.total_ms() * 1e-3 + t.median;
  r.gen_ms = gen_s * 1e3;
  r.trace_ms = t.median * 1e3;
  r.trace_ms_min = t.min * 1e3;
  r.mray_s = t.median > 0 ? rays / t.median * 1e-6 : 0.0;
  if (gs) set_generation(r, *gs);
  r.key_ms = rt.key_ms;
  r.sort_ms = rt.sort_ms;
  r.permute_ms = rt.permute_ms;
  r.e2e_ms = e2e_s * 1e3;
  r.e2e_mray_s = e2e_s > 0 ? rays / e2e_s * 1e-6 : 0.0;
  if (const CoherenceCounters* c = setup_->tracers[ti]->last_counters()) {
    r.simt_efficiency = c->simt_efficiency();
    r.node_simt_efficiency = c->node_simt_efficiency();
    r.lines_per_ray = c->per_ray(c->node_lines + c->triangle_lines);
    r.fetches_per_ray = c->fetches_per_ray();
    r.l1_misses_per_ray = c->l1_misses_per_ray();
    r.l2_misses_per_ray = c->l2_misses_per_ray();
    r.dram_bytes_per_ray = c->dram_bytes_per_ray();
    if (c->modeled.ms > 0) {
      const double e2e_ms = c->modeled.ms + stages.gen_ms + stages.reorder_ms();
      r.modeled_ms = c->modeled.ms;
      r.modeled_mray_s = c->modeled_mray_s();
      r.modeled_e2e_ms = e2e_ms;
      r.modeled_e2e_mray_s = rays / e2e_ms * 1e-3;
      r.modeled_limiter = modeled_limiter(c->modeled);
    }
  }
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
    if (resumed(r, ti)) continue;
    const Timing t = measure(ti, [&] { setup_->tracers[ti]->trace(rays.data(), rays.size(), hits_.data()); });
    r.rays = rays.size();
    record(std::move(r), ti, 0.0, t, nullptr, ReorderTimings{}, ModeledStages{});
  }
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
    std::vector<std::pair<size_t, ExperimentRow>> todo;  // tracer index, row head
    for (size_t ti = 0; ti < o_.tracers.size(); ++ti)
      if (ExperimentRow r = head("secondary", mi, ti, frame); !resumed(r, ti)) todo.emplace_back(ti, std::move(r));
    if (todo.empty()) continue;
    const std::string gen_key = o_.methods[mi].generator.name + ":" + generators_[mi]->params();
    if (gen_key != batch_of) {
      const auto t_gen = Clock::now();
      generators_[mi]->generate(setup_->scene, gbuffer, o_.seed, batch_, gs);
      gen_s = seconds_since(t_gen);
      batch_of = gen_key;
    }
    ReorderTimings rt;
    const bool reordered = reorder(*setup_->encoders[mi], batch_, permute_, sorted_, order_, rt);
    const bool indirect = reordered && permute_ == PermuteMode::Indirect;
    const std::vector<Ray>& rays = reordered && !indirect ? sorted_.rays : batch_.rays;
    hits_.resize(batch_.size());
    for (auto& [ti, r] : todo) {
      Tracer& tracer = *setup_->tracers[ti];
      const Timing t = measure(ti, [&] {
        if (indirect)
          tracer.trace_indirect(rays.data(), order_.data(), rays.size(), hits_.data());
        else
          tracer.trace(rays.data(), rays.size(), hits_.data());
      });
      r.rays = batch_.size();
      const GpuModelConfig* gpu = tracer.gpu_model();
      record(std::move(r), ti, gen_s, t, &gs, rt, gpu ? model_stages(*gpu, mi, reordered) : ModeledStages{});
    }
  }
}

}  // namespace

std::vector<SceneResult> run_experiment(const ExperimentOptions& options, const Provenance& provenance) {
  return ExperimentRun(options, provenance).run();
}

}  // namespace raycoh
