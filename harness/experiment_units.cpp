#include "harness/experiment_units.h"

#include "records/shard.h"
#include "scenes/scene.h"

namespace raycoh {

const char* pass_name(Pass pass) { return pass == Pass::Primary ? "primary" : "secondary"; }

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
