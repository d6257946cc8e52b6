#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
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

// What join_units reads of one kind's rows, and how it names a row.
struct UnitColumns {
  const std::vector<std::string>& names;
  std::vector<size_t> key;
  bool summary;
  size_t scene, method;

  explicit UnitColumns(const Kind& kind)
      : names(kind.layout.columns),
        key(column_indices(kind.layout.columns, kind.key)),
        summary(kind.id == KindId::ConvergeSummary),
        scene(column_index(kind.layout.columns, kind.scene_column)),
        method(column_index(kind.layout.columns, "method")) {}

  std::string describe(const std::vector<std::string>& row) const {
    std::vector<std::string> parts;
    for (size_t c : key)
      if (c != scene) parts.push_back(names[c] + " " + row[c]);
    return row[scene] + " " + join(parts, " ");
  }
};

// Every input's rows sorted to their units, with those that are there twice or belong to no unit.
struct UnitRows {
  std::vector<std::vector<std::pair<size_t, size_t>>> per_unit;  // the rows (input, row) of each unit
  std::vector<std::string> duplicates, strangers;
  std::set<int> present;
  std::vector<std::string> clocks;  // summary: every clock seen, in order of appearance
};

UnitRows sort_to_units(const UnitColumns& c, const std::vector<Input>& inputs, const std::vector<RunFacts>& facts,
                       const RunUnits& units) {
  UnitRows x;
  x.per_unit.resize(units.keys.size());
  std::map<std::string, std::pair<size_t, size_t>> where;  // key -> (input, row)
  for (size_t f = 0; f < inputs.size(); ++f) {
    if (!inputs[f].rows.empty()) x.present.insert(facts[f].shard.index);
    for (size_t r = 0; r < inputs[f].rows.size(); ++r) {
      const auto& row = inputs[f].rows[r];
      const auto [it, fresh] = where.emplace(row_key(row, c.key), std::make_pair(f, r));
      if (!fresh) {
        x.duplicates.push_back(
            fmt::format("{} in {} line {} and {} line {}", c.describe(row), inputs[it->second.first].path,
                        inputs[it->second.first].lines[it->second.second], inputs[f].path, inputs[f].lines[r]));
        continue;
      }
      // A summary names the scene, not its spec: a summary's unit is found by its method (converge has one scene).
      const auto u = std::find_if(units.keys.begin(), units.keys.end(), [&](const std::string& k) {
        return c.summary ? k == render_unit(units.scenes[0], row[c.method])
                         : k == render_unit(row[c.scene], row[c.method]);
      });
      if (u == units.keys.end()) {
        x.strangers.push_back(fmt::format("{} in {} line {}", c.describe(row), inputs[f].path, inputs[f].lines[r]));
        continue;
      }
      x.per_unit[static_cast<size_t>(u - units.keys.begin())].emplace_back(f, r);
      if (c.summary) {
        const std::string& clock = row[column_index(c.names, "clock")];
        if (std::find(x.clocks.begin(), x.clocks.end(), clock) == x.clocks.end()) x.clocks.push_back(clock);
      }
    }
  }
  return x;
}

// The rows no input holds, and the shards that owe them.
struct MissingRows {
  std::vector<std::string> rows;
  std::map<int, size_t> owed;  // shard -> missing rows
  std::set<int> owning;        // every shard that owns a unit with rows of its own
};

// What one unit lacks: quality its row, converge a frame below its last, a summary a clock others show.
void find_missing_of_unit(const Kind& kind, const UnitColumns& c, const std::vector<Input>& inputs, const UnitRows& x,
                          const RunUnits& units, size_t u, const std::function<void(const std::string&)>& lack) {
  const std::string unit_text =
      fmt::format("{} {}", units.scenes[u / units.methods.size()], units.methods[u % units.methods.size()]);
  if (kind.id == KindId::Quality) {
    if (x.per_unit[u].empty()) lack(unit_text);
  } else if (kind.id == KindId::Converge) {
    std::set<int> frames;
    for (const auto& [f, r] : x.per_unit[u])
      frames.insert(std::atoi(inputs[f].rows[r][column_index(c.names, "frame")].c_str()));
    if (frames.empty()) lack(unit_text + " (every frame)");
    for (int k = 1; !frames.empty() && k < *frames.rbegin(); ++k)
      if (!frames.count(k)) lack(fmt::format("{} frame {}", unit_text, k));
  } else if (u % units.methods.size() != 0) {  // summary: the baseline has no row of its own
    std::set<std::string> have;
    for (const auto& [f, r] : x.per_unit[u]) have.insert(inputs[f].rows[r][column_index(c.names, "clock")]);
    for (const std::string& clock : x.clocks)
      if (!have.count(clock)) lack(fmt::format("{} clock {}", unit_text, clock));
    if (x.clocks.empty()) lack(unit_text + " (every clock)");
  }
}

MissingRows find_missing(const Kind& kind, const UnitColumns& c, const std::vector<Input>& inputs, const UnitRows& x,
                         const RunUnits& units, const std::vector<int>& owner) {
  MissingRows m;
  for (size_t u = 0; u < units.keys.size(); ++u) {
    if (!c.summary || u % units.methods.size() != 0) m.owning.insert(owner[u]);
    find_missing_of_unit(kind, c, inputs, x, units, u, [&](const std::string& what) {
      ++m.owed[owner[u]];
      m.rows.push_back(what);
    });
  }
  return m;
}

// Every problem at once: absent shards, missing rows by the shard that owes them, duplicates, strangers.
std::vector<std::string> unit_problems(const Kind& kind, const UnitRows& x, const MissingRows& m, int count) {
  const auto shard_text = [&](int s) { return fmt::format("{}/{}", s, count); };
  std::vector<std::string> problems, missing_shards;
  for (int s : m.owning)
    if (!x.present.count(s)) missing_shards.push_back(shard_text(s));
  if (!missing_shards.empty())
    problems.push_back(fmt::format("shard(s) {} missing (no input holds a row of theirs)", join(missing_shards, ", ")));
  if (!m.rows.empty()) {
    std::vector<std::string> by_shard;
    for (const auto& [s, n] : m.owed) by_shard.push_back(fmt::format("shard {}: {}", shard_text(s), n));
    problems.push_back(fmt::format("{} {} row(s) missing ({}), e.g. {}", m.rows.size(), kind.name, join(by_shard, ", "),
                                   list_head(m.rows)));
  }
  if (!x.duplicates.empty())
    problems.push_back(
        fmt::format("{} duplicate {} row(s): {}", x.duplicates.size(), kind.name, list_head(x.duplicates)));
  if (!x.strangers.empty())
    problems.push_back(fmt::format("{} {} row(s) of no unit of this run (its --scenes/--generators): {}",
                                   x.strangers.size(), kind.name, list_head(x.strangers)));
  return problems;
}

// One process's order: quality scene-major then generator; converge round by round (frame, then generator);
// the summary by generator, each generator's rows as its shard wrote them.
std::vector<const std::vector<std::string>*> in_process_order(const Kind& kind, const UnitColumns& c,
                                                              const std::vector<Input>& inputs, const UnitRows& x) {
  std::vector<std::pair<std::pair<int, size_t>, std::pair<size_t, size_t>>> order;  // ((frame, unit), (f, r))
  for (size_t u = 0; u < x.per_unit.size(); ++u)
    for (const auto& [f, r] : x.per_unit[u]) {
      const int frame =
          kind.id == KindId::Converge ? std::atoi(inputs[f].rows[r][column_index(c.names, "frame")].c_str()) : 0;
      order.push_back({{frame, u}, {f, r}});
    }
  std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<const std::vector<std::string>*> rows;
  for (const auto& [k, fr] : order) rows.push_back(&inputs[fr.first].rows[fr.second]);
  return rows;
}

// quality (one row per unit), converge (rows for frames 1 .. n of every unit, any n >= 1) and converge's summary
// (every clock the summaries show, for each unit but the baseline's): missing rows are named with the shard
// that owes them, duplicates with both places.
Joined join_units(const Kind& kind, const std::vector<Input>& inputs, const std::vector<RunFacts>& facts,
                  const RunUnits& units, int count) {
  const UnitColumns columns(kind);
  const std::vector<int> owner = deal_units(units.keys, count);
  const UnitRows rows = sort_to_units(columns, inputs, facts, units);
  const MissingRows missing = find_missing(kind, columns, inputs, rows, units, owner);
  Joined j;
  j.problems = unit_problems(kind, rows, missing, count);
  j.rows = in_process_order(kind, columns, inputs, rows);
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
  const Shards shards = read_shards(o.inputs, kind, o.commands);
  if (!shards.any) throw Error(fmt::format("merge: not writing {}: no input holds a row", o.out));
  const RunUnits units = units_of(o.commands, kind, shards.inputs[0].path, shards.any->words);
  Joined rows = join_units(kind, shards.inputs, shards.facts, units, shards.count);
  Shards summaries;
  Joined summary_rows;
  if (converge) {
    summaries = read_shards(summary_paths, csv_kinds()[static_cast<size_t>(KindId::ConvergeSummary)], o.commands);
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
  const Shards shards = read_shards(o.inputs, kind, o.commands);
  return merge_experiment(o, kind, shards.inputs, shards.facts);
}

}  // namespace raycoh
