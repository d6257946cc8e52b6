#include "harness/table.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <map>
#include <unistd.h>

#include "core/error.h"
#include "cpu/bvh_build.h"
#include "cpu/tracer.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "generators/primary.h"
#include "harness/csv.h"

namespace raycoh {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Order of the primary pass: the compact 8x8 tile order every generator uses by default.
constexpr int kPrimaryTile = 8;

struct Timing {
  double median = 0, min = 0;
};

// Times `repeats` traces of the same batch; the first call of a tracer on a scene is preceded by a warm-up.
Timing time_trace(Tracer& tracer, const std::vector<Ray>& rays, std::vector<Hit>& hits, int repeats) {
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = Clock::now();
    tracer.trace(rays.data(), rays.size(), hits.data());
    t.push_back(seconds_since(t0));
  }
  std::sort(t.begin(), t.end());
  return {t[t.size() / 2], t.front()};
}

struct Accumulated {
  double rays = 0, seconds = 0;
  double mray_s() const { return seconds > 0 ? rays / seconds * 1e-6 : 0.0; }
};

bool progress_to_terminal() { return ::isatty(STDERR_FILENO) != 0; }

}  // namespace

std::vector<std::string> table_columns() {
  return {"scene",     "scene_triangles", "pass",      "generator", "generator_params", "tracer",  "tracer_params",
          "width",     "height",          "frame",     "seed",      "rays",             "gen_ms",  "trace_ms",
          "trace_ms_min", "repeats",      "mray_s",    "below_geometric", "below_shading", "non_finite"};
}

int run_table(const TableOptions& o, const Provenance& provenance) {
  // Validate every name and parameter before measuring anything.
  std::vector<std::unique_ptr<Generator>> generators;
  std::vector<std::string> generator_labels;
  bool has_noopt = false;
  for (const PluginSpec& spec : o.generators) {
    generators.push_back(make_generator(spec));
    generator_labels.push_back(spec.name);
    has_noopt |= spec.name == "noopt";
  }
  if (!has_noopt) {  // the ratios need the baseline
    generators.insert(generators.begin(), make_generator({"noopt", ""}));
    generator_labels.insert(generator_labels.begin(), "noopt");
    std::fprintf(stderr, "table: adding generator noopt as the baseline of the ratios\n");
  }
  if (o.frames < 1) throw Error("--frames must be >= 1");

  // A scene that is neither built in nor an existing path is an error before anything is measured.
  const std::vector<std::string> builtins = builtin_scene_names();
  for (const std::string& spec : o.scenes) {
    const std::string name = parse_plugin_spec(spec).name;
    if (std::find(builtins.begin(), builtins.end(), name) == builtins.end() && !std::filesystem::exists(spec))
      throw Error(fmt::format("--scenes: '{}' is neither a built-in scene ({}) nor an existing file or folder", spec,
                              join(builtins)));
  }

  std::vector<std::string> columns = table_columns();
  for (const auto& c : provenance_columns()) columns.push_back(c);
  CsvWriter csv(o.out, columns);
  const std::vector<std::string> prov = provenance_values(provenance);

  // results[scene][tracer label][method] accumulated over frames
  struct SceneResult {
    std::string scene;
    size_t triangles = 0;
    double rays_per_frame = 0;
    std::vector<std::string> tracer_labels;
    std::map<std::string, std::map<std::string, Accumulated>> by_tracer;
    std::map<std::string, double> gen_ms;  // per generator, mean per frame
  };
  std::vector<SceneResult> results;
  const bool tty = progress_to_terminal();
  const auto run_start = Clock::now();

  try {
  for (size_t si = 0; si < o.scenes.size(); ++si) {
    const auto t_load = Clock::now();
    const Scene scene = load_scene(o.scenes[si]);
    const double load_s = seconds_since(t_load);
    const SceneFeatures features = analyse(scene);
    const Bvh bvh = build_bvh(scene);
    std::fprintf(stderr,
                 "[%zu/%zu] %s: %zu triangles, loaded in %.2f s; BVH %zu nodes, %zu leaves, depth %zu, SAH %.1f, "
                 "%.1f MiB, built in %.2f s\n",
                 si + 1, o.scenes.size(), scene.name.c_str(), scene.triangle_count(), load_s, bvh.stats.inner_nodes,
                 bvh.stats.leaves, bvh.stats.max_depth, bvh.stats.sah_cost, bvh.stats.bytes / 1048576.0,
                 bvh.stats.build_seconds);
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
    auto gbuffer_tracer = make_tracer({"cpu", ""}, scene, bvh);
    const std::vector<uint32_t> primary_order =
        make_pixel_order(o.width, o.height, RayOrder::Tile, kPrimaryTile, kPrimaryTile);

    std::vector<Hit> hits;
    RayBatch batch;
    for (int frame = 0; frame < o.frames; ++frame) {
      if (tty) std::fprintf(stderr, "\r    frame %d/%d", frame + 1, o.frames);
      const PrimaryBatch primary =
          make_primary_rays(scene.camera, o.width, o.height, primary_order, o.seed, static_cast<uint32_t>(frame), true);
      hits.resize(primary.rays.size());
      gbuffer_tracer->trace(primary.rays.data(), primary.rays.size(), hits.data());
      const GBuffer gbuffer = make_gbuffer(scene, primary, hits);

      auto write = [&](const std::string& pass, const std::string& gen, const std::string& gen_params, size_t ti,
                       size_t rays, double gen_s, const Timing& t, const GenerationStats* gs) {
        std::vector<std::string> row = {scene.name,
                                        std::to_string(scene.triangle_count()),
                                        pass,
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
                                        std::to_string(o.repeats),
                                        fmt::format("{:.3f}", t.median > 0 ? rays / t.median * 1e-6 : 0.0),
                                        gs ? std::to_string(gs->below_geometric) : "",
                                        gs ? std::to_string(gs->below_shading) : "",
                                        gs ? std::to_string(gs->non_finite) : ""};
        row.insert(row.end(), prov.begin(), prov.end());
        csv.write_row(row);
        Accumulated& acc = res.by_tracer[res.tracer_labels[ti]][gen];
        acc.rays += static_cast<double>(rays);
        acc.seconds += t.median;
      };

      // Primary rays: the coherent bound.
      for (size_t ti = 0; ti < tracers.size(); ++ti) {
        if (frame == 0) tracers[ti]->trace(primary.rays.data(), primary.rays.size(), hits.data());  // warm-up
        const Timing t = time_trace(*tracers[ti], primary.rays, hits, o.repeats);
        write("primary", "primary", "order=tile,tile=8x8", ti, primary.rays.size(), 0.0, t, nullptr);
      }
      for (size_t gi = 0; gi < generators.size(); ++gi) {
        GenerationStats gs;
        const auto t_gen = Clock::now();
        generators[gi]->generate(scene, gbuffer, o.seed, batch, gs);
        const double gen_s = seconds_since(t_gen);
        res.gen_ms[generator_labels[gi]] += gen_s * 1e3 / o.frames;
        res.rays_per_frame = static_cast<double>(batch.size());
        hits.resize(batch.size());
        for (size_t ti = 0; ti < tracers.size(); ++ti) {
          if (frame == 0) tracers[ti]->trace(batch.rays.data(), batch.size(), hits.data());  // warm-up
          const Timing t = time_trace(*tracers[ti], batch.rays, hits, o.repeats);
          write("secondary", generator_labels[gi], generators[gi]->params(), ti, batch.size(), gen_s, t, &gs);
        }
      }
    }
    if (tty) std::fprintf(stderr, "\r\033[K");
    results.push_back(std::move(res));
  }
  } catch (const Error& e) {
    if (csv.rows() == 0) throw;
    throw Error(fmt::format("{} ({} rows measured before this are kept in {})", e.what(), csv.rows(),
                            csv.partial_path()));
  }
  csv.finish();

  // Markdown table: one row per scene and tracer, one column per method, "MRay/s (ratio to NoOpt)".
  std::string header = "| scene | tracer | rays/frame | primary |";
  std::string rule = "|---|---|---:|---:|";
  for (const std::string& g : generator_labels) {
    header += " " + g + " |";
    rule += "---:|";
  }
  std::printf("\nMRay/s (ratio to noopt), %dx%d, %d frame(s), seed %u, median of %d traces per batch\n\n%s\n%s\n",
              o.width, o.height, o.frames, o.seed, o.repeats, header.c_str(), rule.c_str());
  for (const SceneResult& r : results) {
    for (const std::string& tl : r.tracer_labels) {
      const auto& m = r.by_tracer.at(tl);
      const double base = m.at("noopt").mray_s();
      std::string line = fmt::format("| {} | {} | {:.0f} | {:.2f} ({:.2f}x) |", r.scene, tl, r.rays_per_frame,
                                     m.at("primary").mray_s(), base > 0 ? m.at("primary").mray_s() / base : 0.0);
      for (const std::string& g : generator_labels) {
        const double v = m.at(g).mray_s();
        line += fmt::format(" {:.2f} ({:.2f}x) |", v, base > 0 ? v / base : 0.0);
      }
      std::printf("%s\n", line.c_str());
    }
  }
  std::printf("\nGeneration time per frame (ms):");
  for (const SceneResult& r : results) {
    std::printf(" %s:", r.scene.c_str());
    for (const std::string& g : generator_labels) std::printf(" %s %.2f", g.c_str(), r.gen_ms.at(g));
    std::printf(";");
  }
  std::printf("\nWrote %zu rows to %s in %.1f s (%s, %d threads)\n", csv.rows(), o.out.c_str(),
              seconds_since(run_start), provenance.git_revision.c_str(), provenance.threads);
  return 0;
}

}  // namespace raycoh
