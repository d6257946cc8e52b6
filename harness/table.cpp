#include "harness/table.h"

#include <chrono>
#include <cstdio>
#include <fmt/format.h>
#include <set>

#include "core/error.h"

namespace raycoh {

namespace {

std::string cell(double value, double base) { return fmt::format("{:.2f} ({:.2f}x)", value, base > 0 ? value / base : 0.0); }

void print_generation(const std::vector<SceneResult>& results, const std::vector<Method>& methods) {
  std::printf("\nSecondary-ray generation per frame: time, groups by type (diffuse/glossy/hybrid/independent/world), "
              "rays reusing another pixel's direction, rays below the geometric surface (weight 0)\n\n");
  std::printf("| scene | generator | gen ms | groups d/g/h/i/w | reused | below geometric |\n|---|---|---:|---|---:|---:|\n");
  for (const SceneResult& r : results) {
    std::set<std::string> shown;
    for (const Method& m : methods) {
      if (!shown.insert(m.generator.text()).second) continue;  // one row per generator: encoders share its batch
      const GenerationStats& g = r.generation.at(m.label);
      const double rays = g.rays > 0 ? static_cast<double>(g.rays) : 1.0;
      std::printf("| %s | %s | %.2f | %zu/%zu/%zu/%zu/%zu | %.1f%% | %.2f%% |\n", r.scene.c_str(), m.generator.text().c_str(),
                  r.gen_ms.at(m.label), g.groups[1], g.groups[2], g.groups[3], g.groups[0], g.groups[4],
                  100.0 * g.reused_rays / rays, 100.0 * g.below_geometric / rays);
    }
  }
}

// Modelling tracers (`simt`): coherence counters per ray instead of wall-clock speed. The modeled speedup is
// cost(noopt) / cost(method), the ranking the cost model gives (simt/simt.h).
void print_counters(const std::vector<SceneResult>& results, const std::vector<Method>& methods, const std::string& tl,
                    const std::string& header, const std::string& rule) {
  std::printf("\n### %s: SIMT efficiency, L1 / L2 sector misses per ray, modeled cost per ray (modeled speedup over "
              "noopt)\n\n%s\n%s\n",
              tl.c_str(), header.c_str(), rule.c_str());
  std::vector<std::string> rows = {"primary"};
  for (const Method& m : methods) rows.push_back(m.label);
  for (const std::string& label : rows) {
    std::string line = "| " + (label == "primary" ? std::string("primary (coherent bound)") : label) + " |";
    for (const SceneResult& r : results) {
      const auto& m = r.by_tracer.at(tl);
      const Accumulated& a = m.at(label);
      const double base = m.at("noopt").per_ray(m.at("noopt").cost_w), cost = a.per_ray(a.cost_w);
      line += fmt::format(" {:.3f}, {:.2f} / {:.2f}, {:.0f} ({:.2f}x) |", a.per_ray(a.simt_eff_w), a.per_ray(a.l1_w),
                          a.per_ray(a.l2_w), cost, cost > 0 ? base / cost : 0.0);
    }
    std::printf("%s\n", line.c_str());
  }
}

}  // namespace

int run_table(const TableOptions& o, const Provenance& provenance) {
  ExperimentOptions e;
  e.scenes = o.scenes;
  e.methods = method_product(o.generators, o.encoders);
  ensure_baseline(e.methods);
  e.tracers = o.tracers;
  e.width = o.width;
  e.height = o.height;
  e.frames = o.frames;
  e.seed = o.seed;
  e.repeats = o.repeats;
  e.permute = o.permute;
  e.out = o.out;
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<SceneResult> results = run_experiment(e, provenance);

  // The paper's Table 1 layout: methods down, scenes across, one table per tracer.
  std::string header = "| method |", rule = "|---|";
  for (const SceneResult& r : results) {
    const std::string tris =
        r.triangles < 1000 ? fmt::format("{}", r.triangles) : fmt::format("{}K", (r.triangles + 500) / 1000);
    header += fmt::format(" {} ({} tris, {:.0f} rays/frame) |", r.scene, tris, r.rays_per_frame);
    rule += "---:|";
  }
  for (const std::string& tl : results.front().tracer_labels) {
    if (results.front().by_tracer.at(tl).at("noopt").has_counters) {
      print_counters(results, e.methods, tl, header, rule);
      continue;
    }
    std::printf("\n### %s: secondary rays traced, MRay/s (ratio to noopt); %dx%d, %d frame(s), seed %u, median of "
                "%d traces\n\n%s\n%s\n",
                tl.c_str(), o.width, o.height, o.frames, o.seed, o.repeats, header.c_str(), rule.c_str());
    std::vector<std::string> rows = {"primary"};
    for (const Method& m : e.methods) rows.push_back(m.label);
    for (const std::string& label : rows) {
      std::string line = "| " + (label == "primary" ? std::string("primary (coherent bound)") : label) + " |";
      for (const SceneResult& r : results) {
        const auto& m = r.by_tracer.at(tl);
        line += " " + cell(m.at(label).mray_s(), m.at("noopt").mray_s()) + " |";
      }
      std::printf("%s\n", line.c_str());
    }
    std::printf("\n### %s: end to end (generation + key + sort + permute + trace), MRay/s (ratio to noopt), "
                "overhead share\n\n%s\n%s\n",
                tl.c_str(), header.c_str(), rule.c_str());
    for (const Method& method : e.methods) {
      std::string line = "| " + method.label + " |";
      for (const SceneResult& r : results) {
        const auto& m = r.by_tracer.at(tl);
        const Accumulated& a = m.at(method.label);
        line += fmt::format(" {}, {:.0f}% |", cell(a.e2e_mray_s(), m.at("noopt").e2e_mray_s()), 100 * a.overhead_share());
      }
      std::printf("%s\n", line.c_str());
    }
  }
  print_generation(results, e.methods);
  std::printf("\nWrote %s in %.1f s (%s, %d threads; permute %s)\n", o.out.c_str(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
              provenance.git_revision.c_str(), provenance.threads, o.permute.c_str());
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
    // A modelling tracer's wall time is the model's: its cells are modeled cost per ray (speedup over noopt).
    const bool model = m.at("noopt").has_counters;
    auto value = [&](const Accumulated& a) { return model ? a.per_ray(a.cost_w) : a.mray_s(); };
    const double base = value(m.at("noopt"));
    if (model)
      std::printf("\n%s, tracer %s: modeled cost per ray of %s (modeled speedup over noopt, %.0f per ray); %dx%d, "
                  "%d frame(s)\n\n",
                  r.scene.c_str(), tl.c_str(), o.generator.c_str(), base, o.width, o.height, o.frames);
    else
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
        line += label.empty() ? " — |"
                : model       ? fmt::format(" {:.0f} ({:.2f}x) |", value(m.at(label)), base / value(m.at(label)))
                              : " " + cell(value(m.at(label)), base) + " |";
      std::printf("%s\n", line.c_str());
    }
  }
  std::printf("\nWrote %s (%s)\n", o.out.c_str(), provenance.git_revision.c_str());
  return 0;
}

}  // namespace raycoh
