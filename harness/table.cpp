#include "harness/table.h"

#include <chrono>
#include <cstdio>
#include <fmt/format.h>

#include "core/error.h"

namespace raycoh {

namespace {

std::string cell(double value, double base) { return fmt::format("{:.2f} ({:.2f}x)", value, base > 0 ? value / base : 0.0); }

void print_generation(const std::vector<SceneResult>& results, const std::vector<Method>& methods) {
  std::printf("\nSecondary-ray generation per frame: time, groups by type (diffuse/glossy/hybrid/independent/world), "
              "rays reusing another pixel's direction, rays below the geometric surface (weight 0)\n\n");
  std::printf("| scene | method | gen ms | groups d/g/h/i/w | reused | below geometric |\n|---|---|---:|---|---:|---:|\n");
  for (const SceneResult& r : results) {
    for (const Method& m : methods) {
      const GenerationStats& g = r.generation.at(m.label);
      const double rays = g.rays > 0 ? static_cast<double>(g.rays) : 1.0;
      std::printf("| %s | %s | %.2f | %zu/%zu/%zu/%zu/%zu | %.1f%% | %.2f%% |\n", r.scene.c_str(), m.label.c_str(),
                  r.gen_ms.at(m.label), g.groups[1], g.groups[2], g.groups[3], g.groups[0], g.groups[4],
                  100.0 * g.reused_rays / rays, 100.0 * g.below_geometric / rays);
    }
  }
}

}  // namespace

int run_table(const TableOptions& o, const Provenance& provenance) {
  ExperimentOptions e;
  e.scenes = o.scenes;
  for (const PluginSpec& g : o.generators) e.methods.push_back({g.text(), g});
  ensure_baseline(e.methods);
  e.tracers = o.tracers;
  e.width = o.width;
  e.height = o.height;
  e.frames = o.frames;
  e.seed = o.seed;
  e.repeats = o.repeats;
  e.out = o.out;
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<SceneResult> results = run_experiment(e, provenance);

  std::string header = "| scene | tracer | rays/frame | primary |";
  std::string rule = "|---|---|---:|---:|";
  for (const Method& m : e.methods) {
    header += " " + m.label + " |";
    rule += "---:|";
  }
  std::printf("\nSecondary-ray trace speed, MRay/s (ratio to noopt); %dx%d, %d frame(s), seed %u, median of %d "
              "traces per batch\n\n%s\n%s\n",
              o.width, o.height, o.frames, o.seed, o.repeats, header.c_str(), rule.c_str());
  for (const SceneResult& r : results) {
    for (const std::string& tl : r.tracer_labels) {
      const auto& m = r.by_tracer.at(tl);
      const double base = m.at("noopt").mray_s();
      std::string line = fmt::format("| {} | {} | {:.0f} | {} |", r.scene, tl, r.rays_per_frame,
                                     cell(m.at("primary").mray_s(), base));
      for (const Method& method : e.methods) line += " " + cell(m.at(method.label).mray_s(), base) + " |";
      std::printf("%s\n", line.c_str());
    }
  }
  print_generation(results, e.methods);
  std::printf("\nWrote %s in %.1f s (%s, %d threads)\n", o.out.c_str(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
              provenance.git_revision.c_str(), provenance.threads);
  return 0;
}

int run_sweep(const SweepOptions& o, const Provenance& provenance) {
  if (o.generator != "ours" && o.generator != "tile")
    throw Error(fmt::format("--generator {}: sweep varies tile and group size; choose ours or tile", o.generator));
  ExperimentOptions e;
  e.scenes = {o.scene};
  e.methods.push_back({"noopt", {"noopt", ""}});
  std::vector<std::vector<std::string>> labels(o.tiles.size());
  for (size_t ti = 0; ti < o.tiles.size(); ++ti) {
    const auto [tw, th] = o.tiles[ti];
    for (int k : o.groups) {
      if (k > tw * th) {  // K larger than a tile is not a grouping: the cell stays empty
        labels[ti].push_back("");
        continue;
      }
      const std::string params = fmt::format("tile={}x{},k={}", tw, th, k);
      labels[ti].push_back(o.generator + ":" + params);
      e.methods.push_back({labels[ti].back(), {o.generator, params}});
    }
  }
  e.tracers = o.tracers;
  e.width = o.width;
  e.height = o.height;
  e.frames = o.frames;
  e.seed = o.seed;
  e.repeats = o.repeats;
  e.out = o.out;
  const std::vector<SceneResult> results = run_experiment(e, provenance);
  const SceneResult& r = results.front();
  for (const std::string& tl : r.tracer_labels) {
    const auto& m = r.by_tracer.at(tl);
    const double base = m.at("noopt").mray_s();
    std::printf("\n%s, tracer %s: secondary MRay/s of %s (ratio to noopt %.2f MRay/s); %dx%d, %d frame(s)\n\n",
                r.scene.c_str(), tl.c_str(), o.generator.c_str(), base, o.width, o.height, o.frames);
    std::string header = "| (W,H) |", rule = "|---|";
    for (int k : o.groups) {
      header += fmt::format(" K = {} |", k);
      rule += "---:|";
    }
    std::printf("%s\n%s\n", header.c_str(), rule.c_str());
    for (size_t ti = 0; ti < o.tiles.size(); ++ti) {
      std::string line = fmt::format("| ({},{}) |", o.tiles[ti].first, o.tiles[ti].second);
      for (const std::string& label : labels[ti])
        line += label.empty() ? " — |" : " " + cell(m.at(label).mray_s(), base) + " |";
      std::printf("%s\n", line.c_str());
    }
  }
  std::printf("\nWrote %s (%s)\n", o.out.c_str(), provenance.git_revision.c_str());
  return 0;
}

}  // namespace raycoh
