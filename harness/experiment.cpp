#include "harness/experiment.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <memory>

#include "core/error.h"
#include "bvh/bvh_build.h"
#include "tracers/tracer.h"
#include "encoders/encoder.h"
#include "encoders/reorder.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "generators/primary.h"
#include "harness/csv.h"
#include "harness/progress.h"

namespace raycoh {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The primary pass uses the compact 8x8 tile order every generator uses by default.
constexpr int kPrimaryTile = 8;

struct Timing {
  double median = 0, min = 0;
};

// Times `repeats` calls of fn; reports the median and the fastest.
template <class Fn>
Timing time_calls(Fn&& fn, int repeats) {
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = Clock::now();
    fn();
    t.push_back(seconds_since(t0));
  }
  std::sort(t.begin(), t.end());
  return {t[t.size() / 2], t.front()};
}

// Same for calls that report their own device time in milliseconds.
template <class Fn>
Timing time_device(Fn&& fn, int repeats) {
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r) t.push_back(fn() * 1e-3);
  std::sort(t.begin(), t.end());
  return {t[t.size() / 2], t.front()};
}

const char* const kPrimaryParams = "order=tile,tile=8x8";

std::string row_key(const std::vector<std::string>& fields) {
  std::string k;
  for (const std::string& f : fields) k += f + '\x1f';
  return k;
}

double number(const std::string& s) { return s.empty() ? 0.0 : std::stod(s); }

// Adds one CSV row (new or resumed) to the scene's sums; the generation statistics are the same in every
// tracer's row of a batch, so only the first tracer's row counts them.
void accumulate_row(const CsvWriter& csv, const std::vector<std::string>& row, SceneResult& res,
                    const std::string& tracer_label, const std::string& label, bool first_tracer, int frames) {
  Accumulated& acc = res.by_tracer[tracer_label][label];
  const double rays = number(row[csv.column("rays")]);
  const double gen_ms = number(row[csv.column("gen_ms")]);
  acc.rays += rays;
  acc.trace_s += number(row[csv.column("trace_ms")]) * 1e-3;
  acc.gen_s += gen_ms * 1e-3;
  acc.reorder_s += (number(row[csv.column("key_ms")]) + number(row[csv.column("sort_ms")]) +
                    number(row[csv.column("permute_ms")])) * 1e-3;
  ++acc.frames;
  if (!row[csv.column("simt_efficiency")].empty()) {
    acc.has_counters = true;
    acc.simt_eff_w += rays * number(row[csv.column("simt_efficiency")]);
    acc.lines_w += rays * number(row[csv.column("lines_per_ray")]);
    acc.l1_w += rays * number(row[csv.column("l1_misses_per_ray")]);
    acc.l2_w += rays * number(row[csv.column("l2_misses_per_ray")]);
    acc.dram_w += rays * number(row[csv.column("dram_bytes_per_ray")]);
    acc.cost_w += rays * number(row[csv.column("modeled_cost_per_ray")]);
  }
  if (row[csv.column("pass")] != "secondary" || !first_tracer) return;
  res.rays_per_frame = rays;
  res.gen_ms[label] += gen_ms / frames;
  GenerationStats& g = res.generation[label];
  auto add = [&](size_t& field, const char* column) { field += static_cast<size_t>(number(row[csv.column(column)])); };
  g.rays += static_cast<size_t>(rays);
  add(g.below_geometric, "below_geometric");
  add(g.below_shading, "below_shading");
  add(g.non_finite, "non_finite");
  add(g.groups[1], "groups_diffuse");
  add(g.groups[2], "groups_glossy");
  add(g.groups[3], "groups_hybrid");
  add(g.groups[0], "groups_independent");
  add(g.groups[4], "groups_world");
  add(g.hybrid_mean_fallback, "hybrid_mean_fallback");
  add(g.reused_rays, "reused_rays");
}

}  // namespace

void ensure_baseline(std::vector<Method>& methods) {
  for (const Method& m : methods)
    if (m.label == "noopt") return;
  methods.insert(methods.begin(), Method{"noopt", {"noopt", ""}});
  std::fprintf(stderr, "adding generator noopt as the baseline of the ratios\n");
}

std::vector<Method> method_product(const std::vector<PluginSpec>& generators, const std::vector<PluginSpec>& encoders) {
  std::vector<Method> methods;
  for (const PluginSpec& g : generators)  // generator-major, so methods sharing a batch are adjacent
    for (const PluginSpec& e : encoders)
      methods.push_back({e.name == "none" ? g.text() : g.text() + "+" + e.text(), g, e});
  return methods;
}

std::vector<std::string> experiment_columns() {
  return {"scene",        "scene_triangles", "pass",          "method",           "generator",
          "generator_params", "tracer",      "tracer_params", "width",            "height",
          "frame",        "seed",            "rays",          "gen_ms",           "trace_ms",
          "trace_ms_min", "repeats",         "mray_s",        "below_geometric",  "below_shading",
          "non_finite",   "groups_diffuse",  "groups_glossy", "groups_hybrid",    "groups_independent",
          "groups_world", "hybrid_mean_fallback", "reused_rays", "encoder",          "encoder_params",
          "permute",      "key_ms",          "sort_ms",       "permute_ms",       "e2e_ms",
          "e2e_mray_s",   "simt_efficiency", "node_simt_efficiency", "lines_per_ray", "fetches_per_ray",
          "l1_misses_per_ray", "l2_misses_per_ray", "dram_bytes_per_ray", "modeled_cost_per_ray"};
}

std::vector<SceneResult> run_experiment(const ExperimentOptions& o, const Provenance& provenance) {
  // Every name and parameter is checked before anything is measured.
  std::vector<std::unique_ptr<Generator>> generators;
  for (const Method& m : o.methods) generators.push_back(make_generator(m.generator));
  const PermuteMode permute = parse_permute_mode(o.permute);
  RAYCOH_CHECK(std::any_of(o.methods.begin(), o.methods.end(), [](const Method& m) { return m.label == "noopt"; }),
               "the methods must contain the noopt baseline");
  for (const std::string& spec : o.scenes) check_scene_spec("--scenes", spec);

  std::vector<std::string> columns = experiment_columns();
  for (const auto& c : provenance_columns()) columns.push_back(c);
  CsvWriter csv(o.out, columns);
  const std::vector<std::string> prov = provenance_values(provenance);
  // Rows of another code revision are never reused, and are not kept either: one file, one revision.
  const size_t stale = csv.keep_resumed_if(
      [&](const std::vector<std::string>& row) { return row[csv.column("git_revision")] == provenance.git_revision; });
  if (stale > 0)
    std::fprintf(stderr, "resume: dropped %zu rows of another code revision from %s\n", stale, csv.partial_path().c_str());
  std::map<std::string, const std::vector<std::string>*> done;
  for (const auto& row : csv.resumed_rows()) {
    std::vector<std::string> k;
    for (const char* c : {"scene", "pass", "method", "generator_params", "encoder_params", "permute", "tracer",
                          "tracer_params", "width", "height", "frame", "seed", "repeats", "git_revision"})
      k.push_back(row[csv.column(c)]);
    done[row_key(k)] = &row;
  }
  if (!done.empty())
    std::fprintf(stderr, "resuming: %zu rows already measured in %s\n", done.size(), csv.partial_path().c_str());
  Progress progress;
  std::vector<SceneResult> results;

  try {
    for (size_t si = 0; si < o.scenes.size(); ++si) {
      const auto t_load = Clock::now();
      const Scene scene = load_scene(o.scenes[si]);
      const double load_s = seconds_since(t_load);
      const SceneFeatures features = analyse(scene);
      const Bvh bvh = build_bvh(scene);
      std::fprintf(stderr,
                   "[%zu/%zu] %s: %zu triangles, loaded in %.2f s; BVH %zu inner nodes, %zu leaves, depth %zu, "
                   "SAH %.1f, %.1f MiB, built in %.2f s\n",
                   si + 1, o.scenes.size(), scene.name.c_str(), scene.triangle_count(), load_s,
                   bvh.stats.inner_nodes, bvh.stats.leaves, bvh.stats.max_depth, bvh.stats.sah_cost,
                   bvh.stats.bytes / 1048576.0, bvh.stats.build_seconds);
      for (const std::string& s : features.skipped_stages) std::fprintf(stderr, "    skipped: %s\n", s.c_str());

      SceneResult res;
      res.scene = scene.name;
      res.triangles = scene.triangle_count();
      std::vector<std::unique_ptr<Tracer>> tracers;
      for (const PluginSpec& spec : o.tracers) {
        tracers.push_back(make_tracer(spec, scene, bvh));
        const std::string p = tracers.back()->params();
        res.tracer_labels.push_back(p.empty() ? spec.name : spec.name + "[" + p + "]");
      }
      std::vector<std::unique_ptr<Encoder>> encoders;
      for (const Method& m : o.methods) encoders.push_back(make_encoder(m.encoder, EncoderContext{scene.bounds, &bvh}));
      auto gbuffer_tracer = make_tracer({"cpu", ""}, scene, bvh);
      const std::vector<uint32_t> primary_order =
          make_pixel_order(o.width, o.height, RayOrder::Tile, kPrimaryTile, kPrimaryTile);

      std::vector<Hit> hits;
      RayBatch batch, sorted;
      std::vector<uint32_t> order;
      // Timing tracers get one untimed warm-up per scene, then the median of `repeats` calls. Modelling tracers
      // (counters, deterministic) run once: their wall time is the model's, not a GPU's.
      std::vector<bool> warmed(tracers.size(), false), models(tracers.size(), false);
      for (size_t ti = 0; ti < tracers.size(); ++ti) models[ti] = tracers[ti]->last_counters() != nullptr;
      auto measure = [&](size_t ti, auto&& trace_once) {
        if (models[ti]) return time_calls(trace_once, 1);
        if (!warmed[ti]) trace_once();
        warmed[ti] = true;
        // A device tracer reports its kernel time (CUDA events, no transfers): that is the trace time.
        auto timed = [&] {
          trace_once();
          return tracers[ti]->last_device_ms();
        };
        if (tracers[ti]->last_device_ms() >= 0.0) return time_device(timed, o.repeats);
        return time_calls(trace_once, o.repeats);
      };
      for (int frame = 0; frame < o.frames; ++frame) {
        progress.update(si, o.scenes.size(), frame, o.frames, scene.name);
        // The key of a measurement; rows of an interrupted run with the same key are not measured again.
        // Reorderings record how they were applied; `none` and the primary pass have nothing to apply.
        auto permute_text = [&](const Encoder* enc) { return enc && enc->key_bits() > 0 ? o.permute : std::string(); };
        // The same fields, in the same order, as the resume map reads from a resumed row.
        auto key = [&](const std::string& pass, const std::string& label, const std::string& gen_params,
                       const Encoder* enc, size_t ti) {
          return row_key({scene.name, pass, label, gen_params, enc ? enc->params() : "", permute_text(enc),
                          o.tracers[ti].name, tracers[ti]->params(), std::to_string(o.width),
                          std::to_string(o.height), std::to_string(frame), std::to_string(o.seed),
                          std::to_string(models[ti] ? 1 : o.repeats), provenance.git_revision});
        };
        auto record = [&](const std::string& pass, const std::string& label, const std::string& gen,
                          const std::string& gen_params, size_t ti, size_t rays, double gen_s, const Timing& t,
                          const GenerationStats* gs, const Encoder* enc, const ReorderTimings& rt) {
          const double e2e_s = gen_s + rt.total_ms() * 1e-3 + t.median;
          auto count = [&](size_t v) { return gs ? std::to_string(v) : std::string(); };
          std::vector<std::string> row = {scene.name,
                                          std::to_string(scene.triangle_count()),
                                          pass,
                                          label,
                                          gen,
                                          gen_params,
                                          o.tracers[ti].name,
                                          tracers[ti]->params(),
                                          std::to_string(o.width),
                                          std::to_string(o.height),
                                          std::to_string(frame),
                                          std::to_string(o.seed),
                                          std::to_string(rays),
                                          fmt::format("{:.4f}", gen_s * 1e3),
                                          fmt::format("{:.4f}", t.median * 1e3),
                                          fmt::format("{:.4f}", t.min * 1e3),
                                          std::to_string(models[ti] ? 1 : o.repeats),
                                          fmt::format("{:.3f}", t.median > 0 ? rays / t.median * 1e-6 : 0.0),
                                          count(gs ? gs->below_geometric : 0),
                                          count(gs ? gs->below_shading : 0),
                                          count(gs ? gs->non_finite : 0),
                                          count(gs ? gs->groups[1] : 0),
                                          count(gs ? gs->groups[2] : 0),
                                          count(gs ? gs->groups[3] : 0),
                                          count(gs ? gs->groups[0] : 0),
                                          count(gs ? gs->groups[4] : 0),
                                          count(gs ? gs->hybrid_mean_fallback : 0),
                                          count(gs ? gs->reused_rays : 0),
                                          enc ? enc->name() : "",
                                          enc ? enc->params() : "",
                                          permute_text(enc),
                                          fmt::format("{:.4f}", rt.key_ms),
                                          fmt::format("{:.4f}", rt.sort_ms),
                                          fmt::format("{:.4f}", rt.permute_ms),
                                          fmt::format("{:.4f}", e2e_s * 1e3),
                                          fmt::format("{:.3f}", e2e_s > 0 ? rays / e2e_s * 1e-6 : 0.0)};
          const CoherenceCounters* c = tracers[ti]->last_counters();
          for (double v : {c ? c->simt_efficiency() : 0.0, c ? c->node_simt_efficiency() : 0.0,
                           c ? c->per_ray(c->node_lines + c->triangle_lines) : 0.0, c ? c->fetches_per_ray() : 0.0,
                           c ? c->l1_misses_per_ray() : 0.0, c ? c->l2_misses_per_ray() : 0.0,
                           c ? c->dram_bytes_per_ray() : 0.0, c ? c->modeled.ms * 1e6 / static_cast<double>(c->rays) : 0.0})
            row.push_back(c ? fmt::format("{:.6g}", v) : std::string());
          row.insert(row.end(), prov.begin(), prov.end());
          csv.write_row(row);
          accumulate_row(csv, row, res, res.tracer_labels[ti], label, ti == 0, o.frames);
        };
        // Rows already measured by an interrupted run count as measured now.
        auto resumed = [&](const std::string& pass, const std::string& label, const std::string& gen_params,
                           const Encoder* enc, size_t ti) {
          const auto it = done.find(key(pass, label, gen_params, enc, ti));
          if (it == done.end()) return false;
          accumulate_row(csv, *it->second, res, res.tracer_labels[ti], label, ti == 0, o.frames);
          return true;
        };

        bool frame_done = true;
        for (size_t ti = 0; ti < tracers.size() && frame_done; ++ti) {
          frame_done = done.count(key("primary", "primary", kPrimaryParams, nullptr, ti)) > 0;
          for (size_t mi = 0; mi < o.methods.size() && frame_done; ++mi)
            frame_done = done.count(key("secondary", o.methods[mi].label, generators[mi]->params(),
                                        encoders[mi].get(), ti)) > 0;
        }
        if (frame_done) {  // nothing left to measure in this frame: take its rows as they are
          for (size_t ti = 0; ti < tracers.size(); ++ti) {
            resumed("primary", "primary", kPrimaryParams, nullptr, ti);
            for (size_t mi = 0; mi < o.methods.size(); ++mi)
              resumed("secondary", o.methods[mi].label, generators[mi]->params(), encoders[mi].get(), ti);
          }
          continue;
        }

        const PrimaryBatch primary = make_primary_rays(scene.camera, o.width, o.height, primary_order, o.seed,
                                                       static_cast<uint32_t>(frame), true);
        hits.resize(primary.rays.size());
        gbuffer_tracer->trace(primary.rays.data(), primary.rays.size(), hits.data());
        const GBuffer gbuffer = make_gbuffer(scene, primary, hits);

        for (size_t ti = 0; ti < tracers.size(); ++ti) {  // primary rays: the coherent bound
          if (resumed("primary", "primary", kPrimaryParams, nullptr, ti)) continue;
          const Timing t =
              measure(ti, [&] { tracers[ti]->trace(primary.rays.data(), primary.rays.size(), hits.data()); });
          record("primary", "primary", "primary", kPrimaryParams, ti, primary.rays.size(), 0.0, t, nullptr, nullptr,
                 ReorderTimings{});
        }
        // Methods sharing a generator share its batch within a frame (generated once, timed once).
        std::string batch_of;
        double gen_s = 0.0;
        GenerationStats gs;
        for (size_t mi = 0; mi < o.methods.size(); ++mi) {
          const Method& method = o.methods[mi];
          std::vector<size_t> todo;
          for (size_t ti = 0; ti < tracers.size(); ++ti)
            if (!resumed("secondary", method.label, generators[mi]->params(), encoders[mi].get(), ti))
              todo.push_back(ti);
          if (todo.empty()) continue;
          const std::string gen_key = method.generator.name + ":" + generators[mi]->params();
          if (gen_key != batch_of) {
            const auto t_gen = Clock::now();
            generators[mi]->generate(scene, gbuffer, o.seed, batch, gs);
            gen_s = seconds_since(t_gen);
            batch_of = gen_key;
          }
          ReorderTimings rt;
          const bool reordered = reorder(*encoders[mi], batch, permute, sorted, order, rt);
          const bool indirect = reordered && permute == PermuteMode::Indirect;
          const std::vector<Ray>& rays = reordered && !indirect ? sorted.rays : batch.rays;
          hits.resize(batch.size());
          for (size_t ti : todo) {
            auto trace_once = [&] {
              if (indirect)
                tracers[ti]->trace_indirect(rays.data(), order.data(), rays.size(), hits.data());
              else
                tracers[ti]->trace(rays.data(), rays.size(), hits.data());
            };
            const Timing t = measure(ti, trace_once);
            record("secondary", method.label, method.generator.name, generators[mi]->params(), ti, batch.size(),
                   gen_s, t, &gs, encoders[mi].get(), rt);
          }
        }
      }
      progress.clear();
      results.push_back(std::move(res));
    }
  } catch (const Error& e) {
    progress.clear();
    csv.discard_if_empty();
    if (csv.rows() + csv.resumed_rows().size() == 0) throw;
    throw Error(fmt::format("{} ({} rows measured so far are kept in {}; run the same command again to resume)",
                            e.what(), csv.rows() + csv.resumed_rows().size(), csv.partial_path()));
  }
  csv.finish();
  return results;
}

}  // namespace raycoh
