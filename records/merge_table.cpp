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

// table and sweep: every scene x frame x row kind the rows show, the shard owing a missing row from the deal of
// scene x frame x method units (records/shard.h).
int merge_experiment(const MergeOptions& o, const Kind& kind, const std::vector<Input>& inputs,
                     const std::vector<RunFacts>& facts) {
  const std::vector<std::string>& columns = kind.layout.columns;
  const std::vector<size_t> key_columns = column_indices(columns, kind.key);
  const size_t c_scene = column_index(columns, "scene"), c_frame = column_index(columns, "frame"),
               c_method = column_index(columns, "method"), c_pass = column_index(columns, "pass"),
               c_tracer = column_index(columns, "tracer");
  // The kind of row within a scene and frame: the key less scene and frame.
  const auto kind_of = [&](const std::vector<std::string>& row) {
    std::string k;
    for (size_t c : key_columns)
      if (c != c_scene && c != c_frame) k += row[c] + '\x1f';
    return k;
  };
  const auto describe = [&](const std::vector<std::string>& row) {
    return fmt::format("{} frame {} {} {} tracer {}", row[c_scene], row[c_frame], row[c_pass], row[c_method],
                       row[c_tracer]);
  };

  std::map<std::string, std::pair<size_t, size_t>> where;  // key -> (input, row)
  std::vector<std::string> duplicates;
  std::vector<std::vector<std::string>> scene_sequences;
  std::vector<std::vector<std::string>> kind_sequences;  // per file, scene and frame: the kinds in file order
  std::map<std::string, std::map<std::string, const std::vector<std::string>*>> kinds;  // scene -> kind -> a row
  int frames = 0;
  std::set<int> shards_present;
  for (size_t f = 0; f < inputs.size(); ++f) {
    frames = std::max(frames, facts[f].frames);
    if (!inputs[f].rows.empty()) shards_present.insert(facts[f].shard.index);
    std::vector<std::string> scenes;
    std::map<std::pair<std::string, std::string>, std::vector<std::string>> per_frame;
    for (size_t r = 0; r < inputs[f].rows.size(); ++r) {
      const auto& row = inputs[f].rows[r];
      std::string key;
      for (size_t c : key_columns) key += row[c] + '\x1f';
      const auto [it, fresh] = where.emplace(key, std::make_pair(f, r));
      if (!fresh)
        duplicates.push_back(
            fmt::format("{} in {} line {} and {} line {}", describe(row), inputs[it->second.first].path,
                        inputs[it->second.first].lines[it->second.second], inputs[f].path, inputs[f].lines[r]));
      if (std::find(scenes.begin(), scenes.end(), row[c_scene]) == scenes.end()) scenes.push_back(row[c_scene]);
      per_frame[{row[c_scene], row[c_frame]}].push_back(kind_of(row));
      kinds[row[c_scene]].emplace(kind_of(row), &row);
      frames = std::max(frames, std::atoi(row[c_frame].c_str()) + 1);
    }
    scene_sequences.push_back(scenes);
    for (auto& [sf, seq] : per_frame) kind_sequences.push_back(std::move(seq));
  }

  // What is missing: whole shards, and rows of the product scene x frame x kind, each owed by its unit's shard.
  int count = 1;
  size_t empty_files = 0;
  for (const RunFacts& f : facts) {
    if (!f.empty) count = f.shard.count;
    empty_files += f.empty;
  }
  std::vector<std::string> problems, missing_shards, missing_rows;
  for (int s = 0; s < count; ++s)
    if (!shards_present.count(s)) missing_shards.push_back(fmt::format("{}/{}", s, count));
  // An input without rows is a shard that owned no unit (more shards than units): it stands for one absent shard.
  if (missing_shards.size() <= empty_files) missing_shards.clear();
  // The units of the run as the rows show them (every scene x frame x method seen), dealt as the shards dealt them.
  std::set<std::string> methods;
  for (const auto& [scene, by_kind] : kinds)
    for (const auto& [kind, example] : by_kind)
      methods.insert((*example)[c_pass] == "primary" ? std::string("primary") : (*example)[c_method]);
  std::vector<std::string> units;
  for (const auto& [scene, by_kind] : kinds)
    for (int frame = 0; frame < frames; ++frame)
      for (const std::string& m : methods) units.push_back(experiment_unit(scene, frame, m));
  const std::vector<int> dealt = deal_units(units, count);
  std::map<std::string, int> owner_of;
  for (size_t u = 0; u < units.size(); ++u) owner_of[units[u]] = dealt[u];
  std::map<int, size_t> owed;  // shard -> missing rows
  for (const auto& [scene, by_kind] : kinds)
    for (int frame = 0; frame < frames; ++frame)
      for (const auto& [kind, example] : by_kind) {
        std::vector<std::string> row = *example;
        row[c_frame] = std::to_string(frame);
        std::string key;
        for (size_t c : key_columns) key += row[c] + '\x1f';
        if (where.count(key)) continue;
        const std::string method = row[c_pass] == "primary" ? std::string("primary") : row[c_method];
        ++owed[owner_of.at(experiment_unit(scene, frame, method))];
        missing_rows.push_back(describe(row));
      }
  if (!missing_shards.empty())
    problems.push_back(fmt::format("shard(s) {} missing (no input holds a row of theirs)", join(missing_shards, ", ")));
  if (!missing_rows.empty()) {
    std::vector<std::string> by_shard;
    for (const auto& [s, n] : owed) by_shard.push_back(fmt::format("shard {}/{}: {}", s, count, n));
    problems.push_back(fmt::format("{} row(s) missing ({}), e.g. {}", missing_rows.size(), join(by_shard, ", "),
                                   list_head(missing_rows)));
  }
  if (!duplicates.empty())
    problems.push_back(fmt::format("{} duplicate row(s): {}", duplicates.size(), list_head(duplicates)));
  if (!problems.empty()) throw Error(fmt::format("merge: not writing {}: {}", o.out, join(problems, "; ")));

  // Scene, then frame, then the kinds in the order the shards wrote them.
  CsvWriter out(o.out, columns, CsvWriter::Options::once(o.force));
  std::set<std::string> hosts;
  const size_t c_host = column_index(columns, "host");
  size_t rows = 0;
  // Every scene and frame has the same kinds in the same order (a scene's own encoder or tracer parameters aside),
  // so all of them together show the order.
  const std::vector<std::string> order = merged_order(kind_sequences, "primary\x1f");
  for (const std::string& scene : merged_order(scene_sequences)) {
    for (int frame = 0; frame < frames; ++frame)
      for (const std::string& kind : order) {
        if (!kinds[scene].count(kind)) continue;
        std::vector<std::string> row = *kinds[scene].at(kind);
        row[c_frame] = std::to_string(frame);
        std::string key;
        for (size_t c : key_columns) key += row[c] + '\x1f';
        const auto [f, r] = where.at(key);
        out.write_row(inputs[f].rows[r]);
        hosts.insert(inputs[f].rows[r][c_host]);
        ++rows;
      }
  }
  out.finish();
  std::printf("Wrote %s: %zu rows from %zu file(s) of %d shard(s), measured on %s\n", o.out.c_str(), rows,
              inputs.size(), count, join(std::vector<std::string>(hosts.begin(), hosts.end()), ", ").c_str());
  return 0;
}

}  // namespace raycoh::merge_detail
