#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "core/durable_file.h"
#include "core/error.h"
#include "records/converge_row.h"
#include "records/csv.h"
#include "records/experiment_row.h"
#include "records/merge_files.h"
#include "records/quality_row.h"
#include "records/shard.h"

namespace raycoh::merge_detail {

// A total order of the items that keeps the order of every sequence wherever the sequences agree (Kahn's
// algorithm over "a came right before b" edges, ties by first appearance): each shard's rows are a subsequence
// of the single process's order, so the merged order is that order wherever the shards show it.
// Items starting with `lead` come first among the ready ones (the primary pass opens every frame).
std::vector<std::string> merged_order(const std::vector<std::vector<std::string>>& sequences, const std::string& lead) {
  std::vector<std::string> items;
  std::set<std::string> seen;
  for (const auto& seq : sequences)
    for (const std::string& s : seq)
      if (seen.insert(s).second) items.push_back(s);
  if (!lead.empty())
    std::stable_partition(items.begin(), items.end(), [&](const std::string& s) { return s.rfind(lead, 0) == 0; });
  std::map<std::string, size_t> first;
  for (size_t i = 0; i < items.size(); ++i) first[items[i]] = i;
  std::vector<std::set<size_t>> next(items.size());
  std::vector<int> in_degree(items.size(), 0);
  for (const auto& seq : sequences)
    for (size_t i = 1; i < seq.size(); ++i) {
      const size_t a = first[seq[i - 1]], b = first[seq[i]];
      if (a != b && next[a].insert(b).second) ++in_degree[b];
    }
  std::set<size_t> ready;
  for (size_t i = 0; i < items.size(); ++i)
    if (in_degree[i] == 0) ready.insert(i);
  std::vector<std::string> out;
  std::vector<bool> placed(items.size(), false);
  while (out.size() < items.size()) {
    size_t pick;
    if (ready.empty()) {  // the sequences disagree (resumed files): the earliest item not yet placed
      pick = static_cast<size_t>(std::find(placed.begin(), placed.end(), false) - placed.begin());
    } else {
      pick = *ready.begin();
      ready.erase(ready.begin());
    }
    if (placed[pick]) continue;
    placed[pick] = true;
    out.push_back(items[pick]);
    for (size_t b : next[pick])
      if (--in_degree[b] == 0 && !placed[b]) ready.insert(b);
  }
  return out;
}

std::string list_head(const std::vector<std::string>& items, size_t shown) {
  std::vector<std::string> head(items.begin(), items.begin() + static_cast<long>(std::min(shown, items.size())));
  return join(head, "; ") + (items.size() > shown ? "; ..." : "");
}

std::string row_key(const std::vector<std::string>& row, const std::vector<size_t>& key_columns) {
  std::string key;
  for (size_t c : key_columns) key += row[c] + '\x1f';
  return key;
}

std::vector<size_t> column_indices(const std::vector<std::string>& columns, const std::vector<std::string>& names) {
  std::vector<size_t> out;
  for (const std::string& n : names) out.push_back(column_index(columns, n));
  return out;
}

std::vector<std::string> hosts_of(const std::vector<const std::vector<std::string>*>& rows,
                                  const std::vector<std::string>& columns) {
  std::set<std::string> hosts;
  for (const auto* row : rows) hosts.insert((*row)[column_index(columns, "host")]);
  return std::vector<std::string>(hosts.begin(), hosts.end());
}

namespace {

// The columns of an experiment row that merging reads.
struct ExperimentColumns {
  std::vector<size_t> key;
  size_t scene, frame, method, pass, tracer;

  explicit ExperimentColumns(const Kind& kind)
      : key(column_indices(kind.layout.columns, kind.key)),
        scene(column_index(kind.layout.columns, "scene")),
        frame(column_index(kind.layout.columns, "frame")),
        method(column_index(kind.layout.columns, "method")),
        pass(column_index(kind.layout.columns, "pass")),
        tracer(column_index(kind.layout.columns, "tracer")) {}

  // The kind of row within a scene and frame: the key less scene and frame.
  std::string kind_of(const std::vector<std::string>& row) const {
    std::string k;
    for (size_t c : key)
      if (c != scene && c != frame) k += row[c] + '\x1f';
    return k;
  }
  std::string describe(const std::vector<std::string>& row) const {
    return fmt::format("{} frame {} {} {} tracer {}", row[scene], row[frame], row[pass], row[method], row[tracer]);
  }
  // The unit a row belongs to: the primary pass is one unit per scene and frame, every other row its method's.
  std::string unit_method(const std::vector<std::string>& row) const {
    return row[pass] == "primary" ? std::string("primary") : row[method];
  }
};

// Every input's rows indexed: where each key is, the orders the files show, and an example row of every kind.
struct ExperimentRows {
  std::map<std::string, std::pair<size_t, size_t>> where;  // key -> (input, row)
  std::vector<std::string> duplicates;
  std::vector<std::vector<std::string>> scene_sequences;
  std::vector<std::vector<std::string>> kind_sequences;  // per file, scene and frame: the kinds in file order
  std::map<std::string, std::map<std::string, const std::vector<std::string>*>> kinds;  // scene -> kind -> a row
  int frames = 0;
  std::set<int> shards_present;
};

ExperimentRows index_experiment_rows(const ExperimentColumns& c, const std::vector<Input>& inputs,
                                     const std::vector<RunFacts>& facts) {
  ExperimentRows x;
  for (size_t f = 0; f < inputs.size(); ++f) {
    x.frames = std::max(x.frames, facts[f].frames);
    if (!inputs[f].rows.empty()) x.shards_present.insert(facts[f].shard.index);
    std::vector<std::string> scenes;
    std::map<std::pair<std::string, std::string>, std::vector<std::string>> per_frame;
    for (size_t r = 0; r < inputs[f].rows.size(); ++r) {
      const auto& row = inputs[f].rows[r];
      const auto [it, fresh] = x.where.emplace(row_key(row, c.key), std::make_pair(f, r));
      if (!fresh)
        x.duplicates.push_back(
            fmt::format("{} in {} line {} and {} line {}", c.describe(row), inputs[it->second.first].path,
                        inputs[it->second.first].lines[it->second.second], inputs[f].path, inputs[f].lines[r]));
      if (std::find(scenes.begin(), scenes.end(), row[c.scene]) == scenes.end()) scenes.push_back(row[c.scene]);
      per_frame[{row[c.scene], row[c.frame]}].push_back(c.kind_of(row));
      x.kinds[row[c.scene]].emplace(c.kind_of(row), &row);
      x.frames = std::max(x.frames, std::atoi(row[c.frame].c_str()) + 1);
    }
    x.scene_sequences.push_back(scenes);
    for (auto& [sf, seq] : per_frame) x.kind_sequences.push_back(std::move(seq));
  }
  return x;
}

// The shard count of the run (as a file with rows records it) and how many inputs hold no rows.
struct ShardTally {
  int count = 1;
  size_t empty_files = 0;
};

ShardTally tally_shards(const std::vector<RunFacts>& facts) {
  ShardTally t;
  for (const RunFacts& f : facts) {
    if (!f.empty) t.count = f.shard.count;
    t.empty_files += f.empty;
  }
  return t;
}

std::vector<std::string> missing_shards(const ExperimentRows& x, const ShardTally& t) {
  std::vector<std::string> missing;
  for (int s = 0; s < t.count; ++s)
    if (!x.shards_present.count(s)) missing.push_back(fmt::format("{}/{}", s, t.count));
  // An input without rows is a shard that owned no unit (more shards than units): it stands for one absent shard.
  if (missing.size() <= t.empty_files) missing.clear();
  return missing;
}

// The shard that owes each unit of the run as the rows show them (every scene x frame x method seen), dealt as the
// shards dealt them.
std::map<std::string, int> unit_owners(const ExperimentColumns& c, const ExperimentRows& x, int count) {
  std::set<std::string> methods;
  for (const auto& [scene, by_kind] : x.kinds)
    for (const auto& [kind, example] : by_kind) methods.insert(c.unit_method(*example));
  std::vector<std::string> units;
  for (const auto& [scene, by_kind] : x.kinds)
    for (int frame = 0; frame < x.frames; ++frame)
      for (const std::string& m : methods) units.push_back(experiment_unit(scene, frame, m));
  const std::vector<int> dealt = deal_units(units, count);
  std::map<std::string, int> owner_of;
  for (size_t u = 0; u < units.size(); ++u) owner_of[units[u]] = dealt[u];
  return owner_of;
}

// The rows of the product scene x frame x kind that no input holds, and how many each shard owes.
std::vector<std::string> missing_rows(const ExperimentColumns& c, const ExperimentRows& x, int count,
                                      std::map<int, size_t>& owed) {
  const std::map<std::string, int> owner_of = unit_owners(c, x, count);
  std::vector<std::string> missing;
  for (const auto& [scene, by_kind] : x.kinds)
    for (int frame = 0; frame < x.frames; ++frame)
      for (const auto& [kind, example] : by_kind) {
        std::vector<std::string> row = *example;
        row[c.frame] = std::to_string(frame);
        if (x.where.count(row_key(row, c.key))) continue;
        ++owed[owner_of.at(experiment_unit(scene, frame, c.unit_method(row)))];
        missing.push_back(c.describe(row));
      }
  return missing;
}

// What is missing (whole shards, and rows each owed by its unit's shard) and what is there twice.
std::vector<std::string> experiment_problems(const ExperimentColumns& c, const ExperimentRows& x, const ShardTally& t) {
  std::vector<std::string> problems;
  const std::vector<std::string> shards = missing_shards(x, t);
  std::map<int, size_t> owed;  // shard -> missing rows
  const std::vector<std::string> rows = missing_rows(c, x, t.count, owed);
  if (!shards.empty())
    problems.push_back(fmt::format("shard(s) {} missing (no input holds a row of theirs)", join(shards, ", ")));
  if (!rows.empty()) {
    std::vector<std::string> by_shard;
    for (const auto& [s, n] : owed) by_shard.push_back(fmt::format("shard {}/{}: {}", s, t.count, n));
    problems.push_back(
        fmt::format("{} row(s) missing ({}), e.g. {}", rows.size(), join(by_shard, ", "), list_head(rows)));
  }
  if (!x.duplicates.empty())
    problems.push_back(fmt::format("{} duplicate row(s): {}", x.duplicates.size(), list_head(x.duplicates)));
  return problems;
}

// Scene, then frame, then the kinds in the order the shards wrote them.
void write_experiment(const MergeOptions& o, const Kind& kind, const ExperimentColumns& c,
                      const std::vector<Input>& inputs, const ExperimentRows& x, int count) {
  const std::vector<std::string>& columns = kind.layout.columns;
  CsvWriter out(o.out, columns, CsvWriter::Options::once(o.force));
  std::set<std::string> hosts;
  const size_t c_host = column_index(columns, "host");
  size_t rows = 0;
  // Every scene and frame has the same kinds in the same order (a scene's own encoder or tracer parameters aside),
  // so all of them together show the order.
  const std::vector<std::string> order = merged_order(x.kind_sequences, "primary\x1f");
  for (const std::string& scene : merged_order(x.scene_sequences)) {
    const auto& by_kind = x.kinds.at(scene);  // every scene of a sequence has its kinds
    for (int frame = 0; frame < x.frames; ++frame)
      for (const std::string& k : order) {
        if (!by_kind.count(k)) continue;
        std::vector<std::string> row = *by_kind.at(k);
        row[c.frame] = std::to_string(frame);
        const auto [f, r] = x.where.at(row_key(row, c.key));
        out.write_row(inputs[f].rows[r]);
        hosts.insert(inputs[f].rows[r][c_host]);
        ++rows;
      }
  }
  out.finish();
  std::printf("Wrote %s: %zu rows from %zu file(s) of %d shard(s), measured on %s\n", o.out.c_str(), rows,
              inputs.size(), count, join(std::vector<std::string>(hosts.begin(), hosts.end()), ", ").c_str());
}

}  // namespace

// table and sweep: every scene x frame x row kind the rows show, the shard owing a missing row from the deal of
// scene x frame x method units (records/shard.h).
int merge_experiment(const MergeOptions& o, const Kind& kind, const std::vector<Input>& inputs,
                     const std::vector<RunFacts>& facts) {
  const ExperimentColumns columns(kind);
  const ExperimentRows rows = index_experiment_rows(columns, inputs, facts);
  const ShardTally shards = tally_shards(facts);
  const std::vector<std::string> problems = experiment_problems(columns, rows, shards);
  if (!problems.empty()) throw Error(fmt::format("merge: not writing {}: {}", o.out, join(problems, "; ")));
  write_experiment(o, kind, columns, inputs, rows, shards.count);
  return 0;
}

}  // namespace raycoh::merge_detail
