// `--shard I/N`: one of N processes (a Slurm array task, a machine) measures a fixed part of a run's work list.
//
// The work list is split into units that share no work: for `table` and `sweep` a unit is one scene x frame x
// method, or the scene x frame primary pass (its rows are one per tracer). A unit belongs to shard
// hash(unit key) mod N, the hash being FNV-1a of the key's text mixed by splitmix64's finalizer: it depends on
// the unit's names only, never on list order or on which other units exist, so every shard decides alone, the
// N shards together hold every unit exactly once, and `raycoh merge` can say which shard a missing row is owed by.
#pragma once

#include <cstdint>
#include <string>

namespace raycoh {

struct Shard {
  int index = 0, count = 1;  // index in [0, count); count 1: the whole run
  bool whole() const { return count == 1; }
  bool owns(const std::string& unit_key) const { return owner(unit_key, count) == index; }
  std::string text() const { return std::to_string(index) + "/" + std::to_string(count); }
  // The shard of `count` that owns a unit.
  static int owner(const std::string& unit_key, int count);
};

constexpr int kMaxShards = 100000;

// "I/N" with N in [1, kMaxShards] and I in [0, N); throws raycoh::Error naming the option.
Shard parse_shard(const std::string& option, const std::string& text);

// The unit key of a table/sweep unit: scene name, frame and method label ("primary" for the primary pass).
std::string experiment_unit(const std::string& scene, int frame, const std::string& method);

}  // namespace raycoh
