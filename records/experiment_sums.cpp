#include "records/experiment_sums.h"

#include <cmath>

#include "records/schema.h"

namespace raycoh {

namespace {

// A row's repeats from its samples column, or its median alone (older rows, one repeat).
std::vector<double> repeats_of(const ResultCsv& c, const std::vector<std::string>& r, const char* samples,
                               double median) {
  if (c.has(samples) && !c.get(r, samples).empty()) return csv_format::Numbers::read(c.get(r, samples));
  return {median};
}

void add_times(const ResultCsv& c, const std::vector<std::string>& r, Sums& s) {
  const int frame = static_cast<int>(c.num(r, "frame"));
  const double rays = c.num(r, "rays");
  const double gpu_e2e = c.has("gpu_e2e_ms") ? c.num(r, "gpu_e2e_ms") : std::nan("");
  s.trace_times[frame] = {repeats_of(c, r, "trace_samples_ms", c.num(r, "trace_ms")), rays};
  s.e2e_times[frame] = {repeats_of(c, r, "e2e_samples_ms", std::isnan(gpu_e2e) ? c.num(r, "e2e_ms") : gpu_e2e), rays};
}

}  // namespace

Experiment read_experiment(const ResultCsv& c) {
  Experiment e;
  std::map<std::string, std::set<std::string>> frames_of;
  for (const auto& r : c.rows) {
    if (c.has("run_under") && !c.get(r, "run_under").empty()) {
      ++e.not_timings;
      e.run_under.insert(c.get(r, "run_under"));
      continue;
    }
    const RecordedColumns recorded = recorded_of(c, r);
    const std::string scene = c.get(r, "scene"), tl = tracer_label(c.get(r, "tracer"), recorded),
                      method = c.get(r, "method");
    add_unique(e.scenes, scene);
    add_unique(e.tracers, tl);
    add_unique(e.methods, method);
    const bool modeled = !std::isnan(c.num(r, "modeled_ms"));
    e.modeled[tl] = modeled;
    Sums& s = e.sums[scene][tl][method];
    s.generator = c.get(r, "generator");
    s.recorded = recorded;
    s.encoder = c.get(r, "encoder").empty() ? "none" : c.get(r, "encoder");
    s.rays += c.num(r, "rays");
    s.trace_ms += c.num(r, "trace_ms");
    s.e2e_ms += c.num(r, "e2e_ms");
    if (!std::isnan(c.num(r, "gpu_e2e_ms"))) s.gpu_e2e_ms += c.num(r, "gpu_e2e_ms");
    add_times(c, r, s);
    if (modeled) {
      s.modeled_ms += c.num(r, "modeled_ms");
      s.modeled_e2e_ms += c.num(r, "modeled_e2e_ms");
    }
    e.revisions.insert(c.get(r, "git_revision"));
    e.resolutions.insert(c.get(r, "width") + "×" + c.get(r, "height"));
    frames_of[scene].insert(c.get(r, "frame"));
    e.cpus.insert(c.get(r, "cpu") + ", " + c.get(r, "threads") + " threads");
    e.commands.insert(c.get(r, "command_line"));
  }
  for (const auto& [scene, f] : frames_of) e.frames.insert(std::to_string(f.size()));
  return e;
}

}  // namespace raycoh
