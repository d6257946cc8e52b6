// `raycoh table`: runs every generator with every encoder and prints, per tracer, trace-only and end-to-end
// MRay/s with ratios to noopt (for `simt`: the GPU timing model's modeled MRay/s, labelled modeled, with the
// coherence counters), then a generation table.
#include "harness/speed/table.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <set>

#include "core/error.h"
#include "encoders/encoder.h"
#include "harness/common/cli.h"
#include "harness/common/command.h"
#include "harness/speed/experiment_cli.h"
#include "records/provenance.h"
#include "records/speed_interval.h"

namespace raycoh {

std::string ratio_cell(double value, double base) {
  return fmt::format("{:.2f} ({:.2f}x)", value, base > 0 ? value / base : 0.0);
}

std::string ratio_cell(double value, const SpeedRatio& r, bool base) {
  return base ? ratio_cell(value, value) : fmt::format("{:.2f} ({})", value, ratio_text(r));
}

namespace {

// Row labels of the per-tracer tables: the coherent bound first, then every method.
std::vector<std::string> row_labels(const std::vector<Method>& methods) {
  std::vector<std::string> rows = {"primary"};
  for (const Method& m : methods) rows.push_back(m.label);
  return rows;
}

std::string row_name(const std::string& label) {
  return "| " + (label == "primary" ? std::string("primary (coherent bound)") : label) + " |";
}

void print_generation(const std::vector<SceneResult>& results, const std::vector<Method>& methods) {
  std::printf(
      "\nSecondary-ray generation per frame: time, groups by type (diffuse/glossy/hybrid/independent/world), "
      "rays reusing another pixel's direction, rays below the geometric surface (weight 0)\n\n");
  std::printf(
      "| scene | generator | gen ms | groups d/g/h/i/w | reused | below geometric |\n|---|---|---:|---|---:|---:|\n");
  for (const SceneResult& r : results) {
    std::set<std::string> shown;
    for (const Method& m : methods) {
      if (!shown.insert(m.generator.text()).second) continue;  // one row per generator: encoders share its batch
      const GenerationStats& g = r.generation.at(m.label);
      const double rays = g.rays > 0 ? static_cast<double>(g.rays) : 1.0;
      std::printf("| %s | %s | %.2f | %zu/%zu/%zu/%zu/%zu | %.1f%% | %.2f%% |\n", r.scene.c_str(),
                  m.generator.text().c_str(), r.gen_ms.at(m.label), g.groups[1], g.groups[2], g.groups[3], g.groups[0],
                  g.groups[4], 100.0 * g.reused_rays / rays, 100.0 * g.below_geometric / rays);
    }
  }
}

// The rows of an end-to-end table: methods down, scenes across; speed and share pick measured or modeled figures.
// `interval`: the measured end to end's ratio interval (host pipelines; a device pipeline's is on its span).
void print_e2e_rows(const std::vector<SceneResult>& results, const std::vector<Method>& methods, const ResultKey& tl,
                    double (Accumulated::*speed)() const, double (Accumulated::*share)() const, bool interval) {
  for (const Method& method : methods) {
    std::string line = "| " + method.label + " |";
    for (const SceneResult& r : results) {
      const auto& m = r.by_tracer.at(tl);
      const Accumulated& a = m.at(method.label);
      const std::string cell =
          interval ? ratio_cell((a.*speed)(), measured_ratio(m.at("noopt"), a, true), method.label == "noopt")
                   : ratio_cell((a.*speed)(), (m.at("noopt").*speed)());
      line += fmt::format(" {}, {:.0f}% |", cell, 100 * (a.*share)());
    }
    std::printf("%s\n", line.c_str());
  }
}

// Counting and modelling tracers (`simt`, `cuda:counters=on`): the coherence counters per ray, and for `simt` the
// GPU timing model's figures, labelled modeled: trace-only MRay/s with the ratio to noopt and the port that
// bounded the kernel, then end to end with every stage modeled on the same GPU (never a CPU time).
void print_counters(const std::vector<SceneResult>& results, const std::vector<Method>& methods, const ResultKey& tl,
                    const std::string& name, const std::string& header) {
  const bool model = results.front().by_tracer.at(tl).at("noopt").model.any;
  std::printf("\n### %s: %sSIMT efficiency, L1 / L2 sector misses per ray\n\n%s\n", name.c_str(),
              model ? "MODELED GPU trace, not measured: modeled MRay/s (ratio to noopt), limiter; " : "",
              header.c_str());
  for (const std::string& label : row_labels(methods)) {
    std::string line = row_name(label);
    for (const SceneResult& r : results) {
      const auto& m = r.by_tracer.at(tl);
      const Accumulated& a = m.at(label);
      if (model)
        line +=
            fmt::format(" {}, {};", ratio_cell(a.modeled_mray_s(), m.at("noopt").modeled_mray_s()), a.model.limiter);
      line += fmt::format(" {:.3f}, {:.2f} / {:.2f} |", a.per_ray(a.counters.simt_eff_w), a.per_ray(a.counters.l1_w),
                          a.per_ray(a.counters.l2_w));
    }
    std::printf("%s\n", line.c_str());
  }
  if (!model) return;
  std::printf(
      "\n### %s: MODELED end to end (generation + key + sort + permute + trace, each modeled on the same GPU), "
      "modeled MRay/s (ratio to noopt), overhead share\n\n%s\n",
      name.c_str(), header.c_str());
  print_e2e_rows(results, methods, tl, &Accumulated::modeled_e2e_mray_s, &Accumulated::modeled_overhead_share, false);
}

// What a device pipeline's times are: measured on a GPU, or simulated (a simulator build: GPGPU-Sim's times are a
// second model's, never hardware's).
std::string device_times(const ResultKey& tl) {
  return simulated_device(PluginSpec{tl.tracer, ""}) ? "SIMULATED" : "MEASURED";
}

// Timing tracers: trace-only MRay/s, then end to end with the overhead share. A device pipeline's figures are
// measured on the GPU, every stage; its end to end is also given as the measured span of the whole pass.
void print_speeds(const std::vector<SceneResult>& results, const std::vector<Method>& methods, const ResultKey& tl,
                  const std::string& name, const std::string& header, const ExperimentOptions& o) {
  const bool device = results.front().by_tracer.at(tl).at("noopt").measured.on_device;
  const int repeats = results.front().by_tracer.at(tl).at("noopt").measured.repeats;
  const std::string where =
      device ? " (" + device_times(tl) + " on the GPU: every stage on the device, CUDA events)" : "";
  std::printf(
      "\n### %s%s: secondary rays traced, MRay/s (ratio to noopt [%.0f%% interval]); %dx%d, %d frame(s), seed %u, "
      "median of %d traces\n\n%s\n",
      name.c_str(), where.c_str(), 100 * kSpeedConfidence, o.width, o.height, o.frames, o.seed, repeats,
      header.c_str());
  for (const std::string& label : row_labels(methods)) {
    std::string line = row_name(label);
    for (const SceneResult& r : results) {
      const auto& m = r.by_tracer.at(tl);
      line += " " +
              ratio_cell(m.at(label).mray_s(), measured_ratio(m.at("noopt"), m.at(label), false), label == "noopt") +
              " |";
    }
    std::printf("%s\n", line.c_str());
  }
  std::printf(
      "\n### %s%s: end to end (generation + key + sort + permute + trace), MRay/s (ratio to noopt), "
      "overhead share\n\n%s\n",
      name.c_str(), where.c_str(), header.c_str());
  print_e2e_rows(results, methods, tl, &Accumulated::e2e_mray_s, &Accumulated::overhead_share, !device);
  if (!device) return;
  std::printf(
      "\n### %s: %s GPU end to end as one span (CUDA events from the first generation kernel to the end of "
      "the trace, gaps between the stages included), MRay/s (ratio to noopt)\n\n%s\n",
      name.c_str(), device_times(tl).c_str(), header.c_str());
  for (const Method& method : methods) {
    std::string line = "| " + method.label + " |";
    for (const SceneResult& r : results) {
      const auto& m = r.by_tracer.at(tl);
      const Accumulated& a = m.at(method.label);
      line +=
          " " + ratio_cell(a.gpu_span_mray_s(), measured_ratio(m.at("noopt"), a, true), method.label == "noopt") + " |";
    }
    std::printf("%s\n", line.c_str());
  }
}

// Device pipelines beside GPU models: per method and scene, ms per frame of generation / reordering (key + sort +
// permute) / trace / end to end, measured on the GPU (end to end: the measured span) and modeled on each model.
void print_measured_vs_modeled(const std::vector<SceneResult>& results, const std::vector<Method>& methods,
                               const std::map<ResultKey, std::string>& names) {
  std::vector<ResultKey> measured, modeled;
  for (const ResultKey& tl : results.front().tracers) {
    const Accumulated& a = results.front().by_tracer.at(tl).at("noopt");
    if (a.measured.on_device && !a.counters.any && !a.hw.replayed) measured.push_back(tl);
    if (a.model.any) modeled.push_back(tl);
  }
  if (measured.empty()) return;
  std::printf(
      "\n### Device pipeline (MEASURED on a GPU, SIMULATED in a simulator build) vs modeled GPU, ms per frame: "
      "generation / key+sort+permute / trace / end to end "
      "(measured: CUDA events, end to end the span; modeled: never added to a measured time)\n\n| scene | method |");
  for (const ResultKey& tl : measured) std::printf(" %s %s |", names.at(tl).c_str(), device_times(tl).c_str());
  for (const ResultKey& tl : modeled) std::printf(" %s MODELED |", names.at(tl).c_str());
  std::printf("\n|---|---|%s\n", std::string(3 * (measured.size() + modeled.size()), '-').c_str());
  for (const SceneResult& r : results)
    for (const Method& method : methods) {
      std::string line = "| " + r.scene + " | " + method.label + " |";
      for (const ResultKey& tl : measured) {
        const Accumulated& a = r.by_tracer.at(tl).at(method.label);
        const double f = 1e3 / std::max(a.frames, 1);
        line += fmt::format(" {:.3f} / {:.3f} / {:.3f} / {:.3f} |", a.measured.gen_s * f, a.measured.reorder_s * f,
                            a.measured.trace_s * f, a.measured.gpu_span_s * f);
      }
      for (const ResultKey& tl : modeled) {
        const Accumulated& a = r.by_tracer.at(tl).at(method.label);
        const double f = 1e3 / std::max(a.frames, 1);
        line += fmt::format(" {:.3f} / {:.3f} / {:.3f} / {:.3f} |", a.model.gen_s * f, a.model.reorder_s * f,
                            a.model.trace_s * f, a.model.e2e_s * f);
      }
      std::printf("%s\n", line.c_str());
    }
}

// Header and rule lines: methods down, scenes across.
std::string scene_header(const std::vector<SceneResult>& results) {
  std::string header = "| method |", rule = "|---|";
  for (const SceneResult& r : results) {
    const std::string tris =
        r.triangles < 1000 ? fmt::format("{}", r.triangles) : fmt::format("{}K", (r.triangles + 500) / 1000);
    header += fmt::format(" {} ({} tris, {:.0f} rays/frame) |", r.scene, tris, r.rays_per_frame);
    rule += "---:|";
  }
  return header + "\n" + rule;
}

// Every tracer with what its figures are, by its name in the headings (records/result_key.h heading_labels) and,
// where that leaves parameters out, every parameter.
void print_tracers(const SceneResult& first, const std::map<ResultKey, std::string>& names,
                   const ExperimentOptions& o) {
  std::printf("## raycoh table: %dx%d, %d frame(s), seed %u\n\n", o.width, o.height, o.frames, o.seed);
  for (const ResultKey& tl : first.tracers) {
    const Accumulated& a = first.by_tracer.at(tl).at("noopt");
    const PluginSpec tracer{tl.tracer, ""};
    const std::string what =
        a.model.any                ? "MODELED GPU figures (the GPU timing model, not measured)"
        : simulated_device(tracer) ? std::string(a.counters.any ? "coherence counters; " : "") +
                                         "SIMULATED GPU figures, not hardware (" + device_of(tracer) + ")"
        : a.hw.replayed        ? "MEASURED hardware counters (CUPTI; kernels replayed, no speeds)"
        : a.counters.any       ? "coherence counters"
        : a.measured.on_device ? "MEASURED on the GPU: every batch made, sorted and traced on the device"
                               : "measured on this machine";
    const std::string& name = names.at(tl);
    const std::string full = tl.label(true);
    std::printf("- %s: %s%s\n", name.c_str(), what.c_str(), name == full ? "" : ("; " + full).c_str());
  }
}

// The closing lines: per tracer and scene, the method with the highest end-to-end MRay/s (generation + keys +
// sort + permute + trace; modeled for a GPU model, the measured span for a device pipeline) and its ratio to
// noopt. A measured winner is called fastest only where its paired interval over every other method excludes 1.
void print_winners(const std::vector<SceneResult>& results, const std::vector<Method>& methods,
                   const std::map<ResultKey, std::string>& names) {
  std::vector<std::string> labels;
  for (const Method& method : methods) labels.push_back(method.label);
  std::string lines;
  for (const ResultKey& tl : results.front().tracers) {
    const Accumulated& first = results.front().by_tracer.at(tl).at("noopt");
    if ((first.counters.any && !first.model.any) || first.hw.replayed) continue;  // counters only: no time
    // A cuda tracer under GPGPU-Sim is simulated whichever pipeline made its batches (pipeline=host traces there).
    const std::string kind = first.model.any                               ? "modeled"
                             : simulated_device(PluginSpec{tl.tracer, ""}) ? "simulated GPU"
                             : first.measured.on_device                    ? "measured on the GPU"
                                                                           : "measured";
    for (const SceneResult& r : results) {
      const auto& m = r.by_tracer.at(tl);
      std::string verdict;
      if (first.model.any) {
        const std::string best = fastest_modeled(m, labels);
        verdict = fmt::format("{} {:.2f}x", best,
                              m.at(best).modeled_e2e_mray_s() / std::max(m.at("noopt").modeled_e2e_mray_s(), 1e-30));
      } else {
        verdict = measured_top(m, labels);
      }
      lines += fmt::format("- {} ({}), {}: {}\n", names.at(tl), kind, r.scene, verdict);
    }
  }
  if (!lines.empty())
    std::printf("\nFastest end to end (ratio to noopt [%.0f%% interval]):\n%s", 100 * kSpeedConfidence, lines.c_str());
}

}  // namespace

int print_shard_done(const ExperimentOptions& e, const Provenance& provenance) {
  std::printf(
      "Wrote shard %s of the run to %s (%s); the console tables need every shard: join the shards' files "
      "with raycoh merge\n",
      e.shard.text().c_str(), e.out.c_str(), provenance.git_revision.c_str());
  return 0;
}

std::vector<Method> comparison_methods() {
  std::vector<PluginSpec> reorderings;
  for (const EncoderInfo& e : encoder_infos())
    if (e.name != "none") reorderings.push_back({e.name, ""});
  std::vector<Method> methods = method_product({{"noopt", ""}, {"ours", ""}, {"contiguous", ""}}, {{"none", ""}});
  for (const Method& m : method_product({{"noopt", ""}}, reorderings)) methods.push_back(m);
  return methods;
}

int run_table(const TableOptions& options, const Provenance& provenance) {
  ExperimentOptions e = options.experiment;
  if (options.generators.empty() && options.encoders.empty()) {
    e.methods = comparison_methods();
  } else {
    const std::vector<PluginSpec> generators =
        options.generators.empty() ? std::vector<PluginSpec>{{"noopt", ""}} : options.generators;
    const std::vector<PluginSpec> encoders =
        options.encoders.empty() ? std::vector<PluginSpec>{{"none", ""}} : options.encoders;
    e.methods = method_product(generators, encoders);
  }
  ensure_baseline(e.methods);
  e.tracers = expand_auto(e.tracers);
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<SceneResult> results = run_experiment(e, provenance);
  if (!e.shard.whole()) return print_shard_done(e, provenance);

  const std::string header = scene_header(results);
  const std::map<ResultKey, std::string> names = heading_labels(results.front().tracers);
  print_tracers(results.front(), names, e);
  for (const ResultKey& tl : results.front().tracers) {
    if (results.front().by_tracer.at(tl).at("noopt").hw.replayed)
      print_hw_counters(results, e.methods, tl, names.at(tl), header);
    else if (results.front().by_tracer.at(tl).at("noopt").counters.any)
      print_counters(results, e.methods, tl, names.at(tl), header);
    else
      print_speeds(results, e.methods, tl, names.at(tl), header, e);
  }
  print_measured_vs_modeled(results, e.methods, names);
  print_generation(results, e.methods);
  print_winners(results, e.methods, names);
  std::printf("\nWrote %s in %.1f s (%s, %d threads; permute %s)\n", e.out.c_str(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
              provenance.git_revision.c_str(), provenance.threads, e.permute.c_str());
  return 0;
}

BoundCommand bind_table(CLI::App& parent) {
  struct State {
    TableOptions o;
    ExperimentText text;
    std::string scenes, generators, encoders;
  };
  auto s = std::make_shared<State>();
  s->scenes = join(s->o.experiment.scenes, ",");
  CLI::App* cmd = parent.add_subcommand(
      "table",
      "trace primary and secondary rays; print MRay/s and ratios to NoOpt. With neither --generators nor "
      "--encoders: noopt, ours, contiguous, and noopt with every encoder");
  cmd->add_option("--scenes", s->scenes, "comma-separated scenes (built-in names, files or folders)")
      ->capture_default_str();
  CLI::Option* generators = cmd->add_option("--generators", s->generators,
                                            "comma-separated generators, e.g. noopt (default noopt when "
                                            "--encoders is given)");
  CLI::Option* encoders =
      cmd->add_option("--encoders", s->encoders,
                      "comma-separated reordering encoders, applied to every generator (default none when --generators "
                      "is given)");
  cmd->add_option("--permute", s->o.experiment.permute, "how a reordering is applied: physical or indirect")
      ->capture_default_str();
  bind_experiment(cmd, s->o.experiment, s->text);
  return {cmd, [s, generators, encoders](const Provenance& provenance) {
            s->o.experiment.scenes = split_scenes("--scenes", s->scenes);
            if (generators->count() > 0 || encoders->count() > 0) {
              s->o.generators = split_nonempty("--generators", generators->count() > 0 ? s->generators : "noopt");
              s->o.encoders = split_nonempty("--encoders", encoders->count() > 0 ? s->encoders : "none");
            }
            resolve_experiment(s->o.experiment, s->text);
            return run_table(s->o, provenance);
          }};
}

}  // namespace raycoh
