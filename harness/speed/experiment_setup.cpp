#include "harness/speed/experiment_setup.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "core/durable_file.h"
#include "core/error.h"
#include "harness/common/memory_check.h"
#include "plugins/tracer_registry.h"
#include "records/record_csv.h"
#include "records/recorded_columns.h"
#include "shading/reference.h"
#include "tracers/hw_counters.h"

namespace raycoh {

namespace {

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

// The repeats a row of this run may carry: --repeat, or every tracer's default; counting tracers run once.
std::set<std::string> repeat_values(const ExperimentOptions& o) {
  std::set<std::string> v = {"1"};
  if (o.repeats > 0) v.insert(std::to_string(o.repeats));
  for (const PluginSpec& t : o.tracers) v.insert(std::to_string(tracer_repeats(o, t, false)));
  return v;
}

void check_options(const ExperimentOptions& o) {
  if (o.width < 1 || o.width > 16384 || o.height < 1 || o.height > 16384)
    throw Error(fmt::format("--res {}x{}: width and height must be in [1, 16384]", o.width, o.height));
  if (o.frames < 1 || o.frames > 100000) throw Error(fmt::format("--frames {}: must be in [1, 100000]", o.frames));
  if (o.repeats < 0 || o.repeats > 1000)
    throw Error(fmt::format("--repeat {}: must be in [1, 1000] (or 0: each tracer's default)", o.repeats));
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

}  // namespace

std::vector<std::unique_ptr<Generator>> checked_generators(const ExperimentOptions& o) {
  check_options(o);
  std::vector<std::unique_ptr<Generator>> generators;
  for (const Method& m : o.methods) generators.push_back(make_generator(m.generator));
  return generators;
}

// What rows of an earlier run must hold to be this run's (records/csv.h): everything known before a scene is
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
      .require("repeats", repeat_values(o))
      .require("permute", {o.permute, ""});
  return require_provenance(rule, p);
}

int tracer_repeats(const ExperimentOptions& o, const PluginSpec& tracer, bool model) {
  if (model) return 1;
  if (o.repeats > 0) return o.repeats;
  if (device_of(tracer) == "cpu") return kHostRepeats;
  return simulated_device(tracer) ? 1 : kDeviceRepeats;
}

SceneSetup::SceneSetup(const std::string& spec, const ExperimentOptions& o,
                       const std::vector<std::unique_ptr<Generator>>& generators, std::vector<ResultKey>& keys) {
  const auto t_load = std::chrono::steady_clock::now();
  fingerprint = experiment_fingerprint(spec);
  scene = load_scene(spec);
  const double load_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_load).count();
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
    keys.push_back(result_key(t.name, tracers.back()->params(), tracers.back()->bvh_layout()));
    // Counting tracers, and tracers whose kernels a profiler replays (cuda:counters=hw), run once per row.
    models.push_back(tracers.back()->last_counters() != nullptr || !hw_run_under(*tracers.back()).empty());
    repeats.push_back(tracer_repeats(o, t, models.back()));
    gpu.push_back(gpu_provenance(t));
    pipelines.push_back(tracers.back()->device_pipeline());
  }
  warmed.assign(tracers.size(), false);
  for (const Method& m : o.methods) encoders.push_back(make_encoder(m.encoder, EncoderContext{scene.bounds, &bvh}));
  gbuffer_tracer = make_tracer({"cpu", ""}, scene, bvh);
  // A device pipeline runs every method itself: what it has no device version of is refused before measuring.
  for (size_t ti = 0; ti < tracers.size(); ++ti)
    for (size_t mi = 0; pipelines[ti] && mi < o.methods.size(); ++mi) {
      const std::string why = pipelines[ti]->refusal(o.methods[mi].generator.name, *generators[mi], *encoders[mi]);
      if (!why.empty()) throw Error(fmt::format("tracer '{}' (device pipeline): {}", keys[ti].label(true), why));
    }
}

}  // namespace raycoh
