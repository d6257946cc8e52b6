#include "records/experiment_sums.h"

#include <stdexcept>

#include "records/schema.h"
#include "tracers/hw_counters.h"

namespace raycoh {

bool Experiment::modeled(const ResultKey& tracer) const {
  for (const auto& [scene, r] : results)
    if (const auto it = r.by_tracer.find(tracer); it != r.by_tracer.end())
      for (const auto& [method, a] : it->second)
        if (a.model.any) return true;
  return false;
}

ExperimentRow experiment_row_of(const ResultCsv& c, const std::vector<std::string>& row) {
  ExperimentRow r;
  for (const Column<ExperimentRow>& col : experiment_schema()) {
    if (!c.has(col.name)) continue;
    try {
      col.read(r, c.get(row, col.name));
    } catch (const std::invalid_argument&) {  // left at its default
    }
  }
  r.recorded = recorded_of(c, row);
  return r;
}

Experiment read_experiment(const ResultCsv& c) {
  Experiment e;
  std::map<std::string, std::set<std::string>> frames_of;
  for (const auto& cells : c.rows) {
    const ExperimentRow r = experiment_row_of(c, cells);
    if (!r.provenance.run_under.empty()) {
      ++e.not_timings;
      e.run_under.insert(r.provenance.run_under);
      if (r.provenance.run_under == kHwCountersRunUnder) {
        add_unique(e.hw_scenes, r.scene);
        add_unique(e.hw_methods, r.method);
        e.hw_results[r.scene].scene = r.scene;
        accumulate(r, 1, e.hw_results[r.scene]);
      }
      continue;
    }
    add_unique(e.scenes, r.scene);
    add_unique(e.methods, r.method);
    SceneResult& res = e.results[r.scene];
    res.scene = r.scene;
    res.triangles = r.scene_triangles;
    accumulate(r, 1, res);
    if (const ResultKey key = result_key(r); std::find(e.tracers.begin(), e.tracers.end(), key) == e.tracers.end())
      e.tracers.push_back(key);
    e.method_of[r.method] = {r.generator, r.encoder.empty() ? "none" : r.encoder, r.recorded};
    e.revisions.insert(r.provenance.git_revision);
    e.resolutions.insert(c.get(cells, "width") + "×" + c.get(cells, "height"));
    frames_of[r.scene].insert(c.get(cells, "frame"));
    e.cpus.insert(r.provenance.cpu + ", " + c.get(cells, "threads") + " threads");
    e.commands.insert(r.provenance.command_line);
  }
  for (const auto& [scene, f] : frames_of) e.frames.insert(std::to_string(f.size()));
  return e;
}

}  // namespace raycoh
