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

namespace raycoh {

namespace merge_detail {

namespace {

// The units of a quality or converge run from the command line its rows record.
RunUnits units_of(const MergeCommands& commands, const Kind& kind, const std::string& file,
                  const std::vector<std::string>& words) {
  RunUnits u;
  try {
    u = commands.units(kind.id == KindId::Quality, words);
  } catch (const Error& e) {
    throw Error(fmt::format("merge: {}: the command line its rows record cannot be read: {}", file, e.what()));
  }
  for (const std::string& s : u.scenes)
    for (const std::string& m : u.methods) u.keys.push_back(render_unit(s, m));
  return u;
}

// The rows of one kind of file, checked and put in one process's order.
struct Joined {
  std::vector<const std::vector<std::string>*> rows;
  std::vector<std::string> problems;
};

// quality (one row per unit), converge (rows for frames 1 .. n of every unit, any n >= 1) and converge's summary
// (every clock the summaries show, for each unit but the baseline's): missing rows are named with the shard
// that owes them, duplicates with both places.
Joined join_units(const Kind& kind, const std::vector<Input>& inputs, const std::vector<RunFacts>& facts,
                  const RunUnits& units, int count) {
  const std::vector<std::string>& columns = kind.layout.columns;
  const std::vector<size_t> key_columns = column_indices(columns, kind.key);
  const bool summary = kind.id == KindId::ConvergeSummary;
  const size_t c_scene = column_index(columns, kind.scene_column), c_method = column_index(columns, "method");
  const std::vector<int> owner = deal_units(units.keys, count);
  const auto shard_text = [&](int s) { return fmt::format("{}/{}", s, count); };
  const auto describe = [&](const std::vector<std::string>& row) {
    std::vector<std::string> parts;
    for (size_t c : key_columns)
      if (c != c_scene) parts.push_back(columns[c] + " " + row[c]);
    return row[c_scene] + " " + join(parts, " ");
  };

  Joined j;
  std::map<std::string, std::pair<size_t, size_t>> where;                           // key -> (input, row)
  std::vector<std::vector<std::pair<size_t, size_t>>> per_unit(units.keys.size());  // the rows of each unit
  std::vector<std::string> duplicates, strangers;
  std::set<int> present;
  std::vector<std::string> clocks;  // summary: every clock seen, in order of appearance
  for (size_t f = 0; f < inputs.size(); ++f) {
    if (!inputs[f].rows.empty()) present.insert(facts[f].shard.index);
    for (size_t r = 0; r < inputs[f].rows.size(); ++r) {
      const auto& row = inputs[f].rows[r];
      const auto [it, fresh] = where.emplace(row_key(row, key_columns), std::make_pair(f, r));
      if (!fresh) {
        duplicates.push_back(
            fmt::format("{} in {} line {} and {} line {}", describe(row), inputs[it->second.first].path,
                        inputs[it->second.first].lines[it->second.second], inputs[f].path, inputs[f].lines[r]));
        continue;
      }
      // A summary names the scene, not its spec: a summary's unit is found by its method (converge has one scene).
      const auto u = std::find_if(units.keys.begin(), units.keys.end(), [&](const std::string& k) {
        return summary ? k == render_unit(units.scenes[0], row[c_method])
                       : k == render_unit(row[c_scene], row[c_method]);
      });
      if (u == units.keys.end()) {
        strangers.push_back(fmt::format("{} in {} line {}", describe(row), inputs[f].path, inputs[f].lines[r]));
        continue;
      }
      per_unit[static_cast<size_t>(u - units.keys.begin())].emplace_back(f, r);
      if (summary) {
        const std::string& clock = row[column_index(columns, "clock")];
        if (std::find(clocks.begin(), clocks.end(), clock) == clocks.end()) clocks.push_back(clock);
      }
    }
  }

  std::vector<std::string> missing, missing_shards;
  std::map<int, size_t> owed;  // shard -> missing rows
  const auto lack = [&](size_t u, const std::string& what) {
    ++owed[owner[u]];
    missing.push_back(what);
  };
  std::set<int> owning;
  for (size_t u = 0; u < units.keys.size(); ++u) {
    const std::string unit_text =
        fmt::format("{} {}", units.scenes[u / units.methods.size()], units.methods[u % units.methods.size()]);
    if (!summary || u % units.methods.size() != 0) owning.insert(owner[u]);
    if (kind.id == KindId::Quality) {
      if (per_unit[u].empty()) lack(u, unit_text);
    } else if (kind.id == KindId::Converge) {
      std::set<int> frames;
      for (const auto& [f, r] : per_unit[u])
        frames.insert(std::atoi(inputs[f].rows[r][column_index(columns, "frame")].c_str()));
      if (frames.empty()) lack(u, unit_text + " (every frame)");
      for (int k = 1; !frames.empty() && k < *frames.rbegin(); ++k)
        if (!frames.count(k)) lack(u, fmt::format("{} frame {}", unit_text, k));
    } else if (u % units.methods.size() != 0) {  // summary: the baseline has no row of its own
      std::set<std::string> have;
      for (const auto& [f, r] : per_unit[u]) have.insert(inputs[f].rows[r][column_index(columns, "clock")]);
      for (const std::string& clock : clocks)
        if (!have.count(clock)) lack(u, fmt::format("{} clock {}", unit_text, clock));
      if (clocks.empty()) lack(u, unit_text + " (every clock)");
    }
  }
  for (int s : owning)
    if (!present.count(s)) missing_shards.push_back(shard_text(s));
  if (!missing_shards.empty())
    j.problems.push_back(
        fmt::format("shard(s) {} missing (no input holds a row of theirs)", join(missing_shards, ", ")));
  if (!missing.empty()) {
    std::vector<std::string> by_shard;
    for (const auto& [s, n] : owed) by_shard.push_back(fmt::format("shard {}: {}", shard_text(s), n));
    j.problems.push_back(fmt::format("{} {} row(s) missing ({}), e.g. {}", missing.size(), kind.name,
                                     join(by_shard, ", "), list_head(missing)));
  }
  if (!duplicates.empty())
    j.problems.push_back(
        fmt::format("{} duplicate {} row(s): {}", duplicates.size(), kind.name, list_head(duplicates)));
  if (!strangers.empty())
    j.problems.push_back(fmt::format("{} {} row(s) of no unit of this run (its --scenes/--generators): {}",
                                     strangers.size(), kind.name, list_head(strangers)));

  // One process's order: quality scene-major then generator; converge round by round (frame, then generator);
  // the summary by generator, each generator's rows as its shard wrote them.
  std::vector<std::pair<std::pair<int, size_t>, std::pair<size_t, size_t>>> order;  // ((frame, unit), (f, r))
  for (size_t u = 0; u < units.keys.size(); ++u)
    for (const auto& [f, r] : per_unit[u]) {
      const int frame =
          kind.id == KindId::Converge ? std::atoi(inputs[f].rows[r][column_index(columns, "frame")].c_str()) : 0;
      order.push_back({{frame, u}, {f, r}});
    }
  std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [k, fr] : order) j.rows.push_back(&inputs[fr.first].rows[fr.second]);
  return j;
}

}  // namespace

// quality and converge (with its summaries): the shards' rows joined, or every problem named at once.
int merge_units(const MergeOptions& o, const Kind& kind) {
  const bool converge = kind.id == KindId::Converge;
  std::vector<std::string> summary_paths;
  const std::string summary_out = converge_summary_path(o.out);
  if (converge) {
    for (const std::string& in : o.inputs) summary_paths.push_back(converge_summary_path(in));
    refuse_absent(summary_paths, summary_out);
    refuse_same_files(summary_paths, {o.out, summary_out});
  }
  const Shards shards = read_shards(o.inputs, kind, o.commands.experiment_frames);
  if (!shards.any) throw Error(fmt::format("merge: not writing {}: no input holds a row", o.out));
  const RunUnits units = units_of(o.commands, kind, shards.inputs[0].path, shards.any->words);
  Joined rows = join_units(kind, shards.inputs, shards.facts, units, shards.count);
  Shards summaries;
  Joined summary_rows;
  if (converge) {
    summaries = read_shards(summary_paths, csv_kinds()[static_cast<size_t>(KindId::ConvergeSummary)],
                            o.commands.experiment_frames);
    if (summaries.any && summaries.count != shards.count)
      throw Error(fmt::format("merge: the summaries are of {} shards, the per-frame files of {}", summaries.count,
                              shards.count));
    summary_rows = join_units(csv_kinds()[static_cast<size_t>(KindId::ConvergeSummary)], summaries.inputs,
                              summaries.facts, units, shards.count);
    rows.problems.insert(rows.problems.end(), summary_rows.problems.begin(), summary_rows.problems.end());
  }
  if (!rows.problems.empty()) throw Error(fmt::format("merge: not writing {}: {}", o.out, join(rows.problems, "; ")));

  // Both outputs are opened (refused when they exist, unless --force) before either is written.
  CsvWriter out(o.out, kind.layout.columns, CsvWriter::Options::once(o.force));
  std::unique_ptr<CsvWriter> summary_out_csv;
  if (converge)
    summary_out_csv = std::make_unique<CsvWriter>(
        summary_out, csv_kinds()[static_cast<size_t>(KindId::ConvergeSummary)].layout.columns,
        CsvWriter::Options::once(o.force));
  for (const auto* row : rows.rows) out.write_row(*row);
  out.finish();
  std::printf("Wrote %s: %zu rows from %zu file(s) of %d shard(s), measured on %s\n", o.out.c_str(), rows.rows.size(),
              o.inputs.size(), shards.count, join(hosts_of(rows.rows, kind.layout.columns), ", ").c_str());
  if (converge) {
    for (const auto* row : summary_rows.rows) summary_out_csv->write_row(*row);
    summary_out_csv->finish();
    std::printf("Wrote %s: %zu rows (each ratio against the baseline rendered beside it, on the host of its row)\n",
                summary_out.c_str(), summary_rows.rows.size());
  }
  return 0;
}

}  // namespace merge_detail

int run_merge(const MergeOptions& o, const Provenance& provenance) {
  using namespace merge_detail;
  (void)provenance;
  if (o.inputs.empty()) throw Error("merge: no input files; name the shards' CSV files after --out OUT");
  check_output_file("--out", o.out);
  refuse_same_files(o.inputs, {o.out});
  refuse_absent(o.inputs, o.out);
  const Kind& kind = kind_of_file(o.inputs[0]);
  if (kind.id != KindId::Experiment) return merge_units(o, kind);
  const Shards shards = read_shards(o.inputs, kind, o.commands.experiment_frames);
  return merge_experiment(o, kind, shards.inputs, shards.facts);
}

}  // namespace raycoh
