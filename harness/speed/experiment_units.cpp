#include "harness/speed/experiment_units.h"

#include "encoders/encoder.h"
#include "generators/generator.h"
#include "harness/speed/experiment_setup.h"
#include "records/shard.h"
#include "scenes/scene.h"
#include "tracers/hw_counters.h"
#include "tracers/tracer.h"

namespace raycoh {

const char* pass_name(Pass pass) { return pass == Pass::Primary ? "primary" : "secondary"; }

ExperimentRow unit_head(const ExperimentOptions& o, const SceneSetup& setup, const Provenance& provenance,
                        const std::vector<std::unique_ptr<Generator>>& generators, const Unit& u, size_t ti) {
  const bool primary = u.primary();
  const Encoder* enc = primary ? nullptr : setup.encoders[u.method].get();
  ExperimentRow r;
  r.scene = setup.scene.name;
  r.scene_triangles = setup.scene.triangle_count();
  r.scene_fingerprint = setup.fingerprint;
  r.pass = pass_name(u.pass);
  r.method = primary ? "primary" : o.methods[u.method].label;
  r.generator = primary ? "primary" : o.methods[u.method].generator.name;
  r.generator_params = primary ? kPrimaryParams : generators[u.method]->params();
  r.tracer = o.tracers[ti].name;
  r.tracer_params = setup.tracers[ti]->params();
  r.bvh = setup.tracers[ti]->bvh_layout();
  r.width = o.width;
  r.height = o.height;
  r.frame = u.frame;
  r.seed = o.seed;
  r.repeats = setup.repeats[ti];
  r.encoder = enc ? enc->name() : "";
  r.encoder_params = enc ? enc->params() : "";
  // Reorderings record how they were applied; `none` and the primary pass have nothing to apply.
  r.permute = enc && enc->key_bits() > 0 ? o.permute : "";
  r.provenance = provenance;
  r.provenance.device = device_of(o.tracers[ti]);
  // A tracer whose kernels a profiler replays (cuda:counters=hw) marks its rows: their times are not timings.
  if (const std::string under = hw_run_under(*setup.tracers[ti]); !under.empty()) r.provenance.run_under = under;
  r.gpu = setup.gpu[ti];
  if (primary)
    set_recorded_params(r);
  else
    set_recorded_params(r, *generators[u.method]);  // the generator's typed K, tile and order
  return r;
}

std::vector<Unit> frame_units(const ExperimentOptions& o, size_t scene, int frame) {
  std::vector<Unit> units = {{scene, frame, Pass::Primary, 0}};
  for (size_t mi = 0; mi < o.methods.size(); ++mi) units.push_back({scene, frame, Pass::Secondary, mi});
  return units;
}

ExperimentUnits::ExperimentUnits(const ExperimentOptions& o, const std::vector<ExperimentRow>& resumed) : o_(o) {
  for (const ExperimentRow& row : resumed) done_[resume_key(experiment_schema(), row)] = &row;
  if (o.shard.whole()) return;
  std::vector<std::string> keys;
  for (size_t si = 0; si < o.scenes.size(); ++si)
    for (int frame = 0; frame < o.frames; ++frame)
      for (const Unit& u : frame_units(o, si, frame)) keys.push_back(key(u));
  const std::vector<int> owner = deal_units(keys, o.shard.count);
  for (size_t u = 0; u < keys.size(); ++u)
    if (owner[u] == o.shard.index) owned_.insert(keys[u]);
}

// Units (records/shard.h): scene x frame x method, and the scene x frame primary pass (method "primary").
std::string ExperimentUnits::key(const Unit& u) const {
  return experiment_unit(scene_name_of(o_.scenes[u.scene]), u.frame,
                         u.primary() ? "primary" : o_.methods[u.method].label);
}

bool ExperimentUnits::owns(const Unit& u) const { return o_.shard.whole() || owned_.count(key(u)); }

bool ExperimentUnits::owns_any(size_t scene, int frame) const {
  for (const Unit& u : frame_units(o_, scene, frame))
    if (owns(u)) return true;
  return false;
}

bool ExperimentUnits::owns_any(size_t scene) const {
  for (int frame = 0; frame < o_.frames; ++frame)
    if (owns_any(scene, frame)) return true;
  return false;
}

bool ExperimentUnits::done(const ExperimentRow& head) const {
  return done_.count(resume_key(experiment_schema(), head)) > 0;
}

const ExperimentRow* ExperimentUnits::take(const ExperimentRow& head) {
  const auto it = done_.find(resume_key(experiment_schema(), head));
  if (it == done_.end()) return nullptr;
  used_.insert(it->first);
  return it->second;
}

const ExperimentRow* ExperimentUnits::first_untaken() const {
  for (const auto& [key, row] : done_)
    if (!used_.count(key)) return row;
  return nullptr;
}

}  // namespace raycoh
