// The units of one experiment run (records/shard.h) and what is already known of them before measuring: which units
// this shard owns (--shard I/N) and which rows an interrupted run left (resume). Internal to the experiment loop
// (harness/speed/experiment.cpp).
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "harness/speed/experiment.h"
#include "records/experiment_row.h"

namespace raycoh {

// The two passes of a frame: the primary pass traces the camera rays (the coherent bound, one row per tracer), the
// secondary pass one method's batch (one row per method x tracer).
enum class Pass { Primary, Secondary };

// The pass column's text: "primary" or "secondary".
const char* pass_name(Pass pass);

// One unit of work: the scene x frame primary pass, or one scene x frame x method's secondary pass.
struct Unit {
  size_t scene = 0;  // index into ExperimentOptions::scenes
  int frame = 0;
  Pass pass = Pass::Primary;
  size_t method = 0;  // index into ExperimentOptions::methods; the secondary pass only
  bool primary() const { return pass == Pass::Primary; }
};

class Generator;
struct SceneSetup;

// A unit's row as far as it is known before measuring: its identity and resume key (scene, pass, method, tracer
// and their parameters, size, frame, seed, repeats, provenance, the GPU's facts). `setup` is the scene's tracers and
// encoders (harness/speed/experiment_setup.h), `generators` one per method.
ExperimentRow unit_head(const ExperimentOptions& o, const SceneSetup& setup, const Provenance& provenance,
                        const std::vector<std::unique_ptr<Generator>>& generators, const Unit& u, size_t ti);

// A frame's units in the order they are measured: the primary pass, then every method.
std::vector<Unit> frame_units(const ExperimentOptions& o, size_t scene, int frame);

class ExperimentUnits {
 public:
  // `resumed`: the rows an interrupted run left (they must outlive this object).
  ExperimentUnits(const ExperimentOptions& o, const std::vector<ExperimentRow>& resumed);

  // --shard: whether this shard measures the unit (every unit of a whole run).
  bool owns(const Unit& u) const;
  bool owns_any(size_t scene, int frame) const;
  bool owns_any(size_t scene) const;

  // Resume: whether an interrupted run measured the row with this head's resume key.
  bool done(const ExperimentRow& head) const;
  // That row, counted as this run's (used), or null.
  const ExperimentRow* take(const ExperimentRow& head);
  size_t resumed_rows() const { return done_.size(); }
  // Resumed rows this run did not take (asked for): their count, and the first of them (null when none).
  size_t untaken_rows() const { return done_.size() - used_.size(); }
  const ExperimentRow* first_untaken() const;

 private:
  std::string key(const Unit& u) const;  // records/shard.h experiment_unit

  const ExperimentOptions& o_;
  std::map<std::string, const ExperimentRow*> done_;  // resume key -> resumed row
  std::set<std::string> used_;                        // keys of done_ this run asked for
  std::set<std::string> owned_;                       // --shard: the unit keys this shard measures
};

}  // namespace raycoh
