// `--shard I/N`: one of N processes (a Slurm array task, a machine) measures a fixed part of a run's work list.
//
// The work list is split into units that share no work: for `table` and `sweep` a unit is one scene x frame x
// method, or the scene x frame primary pass (its rows are one per tracer); for `quality` and `converge` one
// scene x generator (the reference is shared through the cache). The units are sorted by a hash of their
// names (FNV-1a mixed by splitmix64's finalizer, then the name) and dealt round-robin: shard sizes differ by at most
// one unit, and a unit's shard depends only on the set of units, never on the order options list them. Every shard
// computes the same deal from the same command, so the N shards together hold every unit exactly once, and
// `raycoh merge` can say which shard owes a missing row.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace raycoh {

struct Shard {
  int index = 0, count = 1;  // index in [0, count); count 1: the whole run
  bool whole() const { return count == 1; }
  std::string text() const { return std::to_string(index) + "/" + std::to_string(count); }
};

constexpr int kMaxShards = 100000;

// "I/N" with N in [1, kMaxShards] and I in [0, N); throws raycoh::Error naming the option.
Shard parse_shard(const std::string& option, const std::string& text);

// The shard (in [0, count)) of each unit; units must be distinct.
std::vector<int> deal_units(const std::vector<std::string>& units, int count);

// The unit key of a table/sweep unit: scene name, frame and method label ("primary" for the primary pass).
std::string experiment_unit(const std::string& scene, int frame, const std::string& method);

// The unit key of a `quality` or `converge` unit: one scene spec x one generator (its method label).
std::string render_unit(const std::string& scene_spec, const std::string& method);

// The units of `units` that shard `shard` owns (all of them for a whole run).
std::vector<bool> owned_units(const std::vector<std::string>& units, const Shard& shard);

}  // namespace raycoh
