#include "harness/merge.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "core/durable_file.h"
#include "core/error.h"
#include "harness/command.h"
#include "harness/csv.h"
#include "harness/experiment.h"
#include "harness/experiment_row.h"
#include "harness/shard.h"

namespace raycoh {

std::vector<std::string> command_words(const std::string& command_line) {
  // The inverse of provenance.cpp's shell_quote: words split at spaces, '...' quoted, '\'' an embedded quote.
  std::vector<std::string> words;
  std::string cur;
  bool in_word = false, quoted = false;
  for (size_t i = 0; i < command_line.size(); ++i) {
    const char c = command_line[i];
    if (quoted) {
      if (c == '\'')
        quoted = false;
      else
        cur += c;
    } else if (c == '\'') {
      quoted = in_word = true;
    } else if (c == '\\' && i + 1 < command_line.size()) {
      cur += command_line[++i];
      in_word = true;
    } else if (c == ' ') {
      if (in_word) words.push_back(cur);
      cur.clear();
      in_word = false;
    } else {
      cur += c;
      in_word = true;
    }
  }
  if (in_word) words.push_back(cur);
  if (!words.empty()) words.erase(words.begin());
  return words;
}

namespace {

// One input file: its rows as written (fields untouched) and what the checks need of them.
struct Input {
  std::string path;
  std::vector<std::vector<std::string>> rows;
  std::vector<size_t> lines;  // the line of each row
};

Input read_input(const std::string& path, const std::vector<std::string>& columns) {
  if (path.size() > 8 && path.compare(path.size() - 8, 8, ".partial") == 0)
    throw Error(
        fmt::format("merge: {} is an unfinished run's file; run that shard's command again (it resumes and "
                    "finishes it), then merge its --out",
                    path));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(fmt::format("merge: {}: cannot read the file", path));
  Input input{path, {}, {}};
  std::string line;
  std::vector<std::string> fields;
  size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!csv_parse_line(line, fields) || line.empty() || line.find('\0') != std::string::npos)
      throw Error(fmt::format("merge: {} line {}: not a CSV record (damaged line)", path, number));
    if (number == 1) {
      if (fields != columns)
        throw Error(
            fmt::format("merge: {}: its columns are not those of this build's table/sweep CSV (first "
                        "header: {} columns, expected {}); merge files written by one build",
                        path, fields.size(), columns.size()));
      continue;
    }
    try {
      read_row(experiment_schema(), fields);
    } catch (const std::invalid_argument& e) {
      throw Error(fmt::format("merge: {} line {}: {}", path, number, e.what()));
    }
    input.rows.push_back(fields);
    input.lines.push_back(number);
  }
  if (number == 0) throw Error(fmt::format("merge: {}: empty file (no header)", path));
  return input;
}

int count_lines(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  int n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

size_t column_index(const std::vector<std::string>& columns, const std::string& name) {
  const auto it = std::find(columns.begin(), columns.end(), name);
  RAYCOH_CHECK(it != columns.end(), "merge: unknown column");
  return static_cast<size_t>(it - columns.begin());
}

std::string joined(const std::set<std::string>& values) {
  std::vector<std::string> v(values.begin(), values.end());
  return join(v, "|");
}

// What a file says about the run it belongs to; two shards of one run agree on every entry.
struct RunFacts {
  std::vector<std::pair<std::string, std::string>> fields;  // field name -> values ("a|b" when several)
  Shard shard;                                              // from the rows' command lines
  std::string command;                                      // the command line less --shard, --out, --force
  int frames = ExperimentOptions{}.frames;
  bool empty = false;  // no rows (a shard that owned no unit): nothing to agree on, its shard unknown
};

RunFacts facts_of(const Input& in, const std::vector<std::string>& columns) {
  RunFacts f;
  f.empty = in.rows.empty();
  for (const char* name : {"git_revision", "build_type", "compiler", "embree_version", "width", "height", "seed"}) {
    std::set<std::string> values;
    for (const auto& row : in.rows) values.insert(row[column_index(columns, name)]);
    f.fields.emplace_back(name, joined(values));
  }
  // Per scene: its fingerprint and its tracers' parameters.
  std::map<std::string, std::set<std::string>> fingerprints, tracers;
  const size_t scene = column_index(columns, "scene"), fp = column_index(columns, "scene_fingerprint"),
               tracer = column_index(columns, "tracer"), tparams = column_index(columns, "tracer_params");
  for (const auto& row : in.rows) {
    fingerprints[row[scene]].insert(row[fp]);
    tracers[row[scene]].insert(row[tracer] + "[" + row[tparams] + "]");
  }
  for (const auto& [s, v] : fingerprints) f.fields.emplace_back("scene_fingerprint of " + s, joined(v));
  for (const auto& [s, v] : tracers) f.fields.emplace_back("tracer_params of " + s, joined(v));
  std::set<std::string> commands, shards;
  for (const auto& row : in.rows) {
    const std::vector<std::string> words = command_words(row[column_index(columns, "command_line")]);
    std::string command, shard = "0/1";
    for (size_t i = 0; i < words.size(); ++i) {
      const std::string& w = words[i];
      if ((w == "--shard" || w == "--out") && i + 1 < words.size()) {
        if (w == "--shard") shard = words[i + 1];
        ++i;
      } else if (w.rfind("--shard=", 0) == 0) {
        shard = w.substr(8);
      } else if (w.rfind("--out=", 0) == 0 || w == "--force") {
      } else {
        if (w == "--frames" && i + 1 < words.size()) f.frames = std::atoi(words[i + 1].c_str());
        if (w.rfind("--frames=", 0) == 0) f.frames = std::atoi(w.c_str() + 9);
        command += (command.empty() ? "" : " ") + w;
      }
    }
    commands.insert(command);
    shards.insert(shard);
  }
  if (shards.size() > 1)
    throw Error(fmt::format("merge: {} holds rows of several shards ({}); merge each shard's own --out", in.path,
                            joined(shards)));
  if (!shards.empty()) f.shard = parse_shard(in.path + ": --shard", *shards.begin());
  f.command = joined(commands);
  return f;
}

// Every run-wide field equal in every file; the first difference is the error.
void check_agreement(const std::vector<Input>& inputs, const std::vector<RunFacts>& facts) {
  for (size_t a = 0; a < inputs.size(); ++a)
    for (size_t b = a + 1; b < inputs.size(); ++b) {
      if (facts[a].empty || facts[b].empty) continue;
      for (const auto& [name, va] : facts[a].fields)
        for (const auto& [name_b, vb] : facts[b].fields)
          if (name == name_b && va != vb)
            throw Error(fmt::format("merge: {} and {} disagree on {}: '{}' vs '{}'; shards of one run must agree",
                                    inputs[a].path, inputs[b].path, name, va, vb));
      if (facts[a].command != facts[b].command)
        throw Error(
            fmt::format("merge: {} and {} disagree on the parameters (command line without --shard, --out "
                        "and --force): '{}' vs '{}'; shards of one run must agree",
                        inputs[a].path, inputs[b].path, facts[a].command, facts[b].command));
      if (facts[a].shard.count != facts[b].shard.count)
        throw Error(fmt::format("merge: {} and {} disagree on the shard count: {} vs {}", inputs[a].path,
                                inputs[b].path, facts[a].shard.text(), facts[b].shard.text()));
    }
}

// A total order of the items that keeps the order of every sequence wherever the sequences agree (Kahn's
// algorithm over "a came right before b" edges, ties by first appearance): each shard's rows are a subsequence
// of the single process's order, so the merged order is that order wherever the shards show it.
// Items starting with `lead` come first among the ready ones (the primary pass opens every frame).
std::vector<std::string> merged_order(const std::vector<std::vector<std::string>>& sequences,
                                      const std::string& lead = "") {
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

std::string list_head(const std::vector<std::string>& items, size_t shown = 3) {
  std::vector<std::string> head(items.begin(), items.begin() + static_cast<long>(std::min(shown, items.size())));
  return join(head, "; ") + (items.size() > shown ? "; ..." : "");
}

}  // namespace

int run_merge(const MergeOptions& o, const Provenance& provenance) {
  (void)provenance;
  if (o.inputs.empty()) throw Error("merge: no input files; name the shards' CSV files after --out OUT");
  check_output_file("--out", o.out);
  std::error_code ec;
  for (size_t i = 0; i < o.inputs.size(); ++i) {
    if (std::filesystem::equivalent(o.inputs[i], o.out, ec))
      throw Error(fmt::format("merge: --out {} is one of the inputs; write the merged file elsewhere", o.out));
    for (size_t j = 0; j < i; ++j)
      if (std::filesystem::equivalent(o.inputs[i], o.inputs[j], ec))
        throw Error(fmt::format("merge: {} and {} are the same file; name each shard once", o.inputs[j], o.inputs[i]));
  }
  // Inputs that are not there (a shard that failed or is still running) are listed together.
  std::vector<std::string> absent;
  for (const std::string& path : o.inputs) {
    if (std::filesystem::exists(path, ec)) continue;
    const std::string partial = path + ".partial";
    absent.push_back(
        std::filesystem::exists(partial, ec)
            ? fmt::format("{} (unfinished: {} holds {} row(s); run that shard's command again, it resumes)", path,
                          partial, std::max<int>(0, count_lines(partial) - 1))
            : fmt::format("{} (no such file)", path));
  }
  if (!absent.empty())
    throw Error(fmt::format("merge: not writing {}: {} of {} input(s) missing: {}", o.out, absent.size(),
                            o.inputs.size(), join(absent, "; ")));
  const std::vector<std::string> columns = column_names(experiment_schema());
  std::vector<Input> inputs;
  std::vector<RunFacts> facts;
  for (const std::string& path : o.inputs) {
    inputs.push_back(read_input(path, columns));
    facts.push_back(facts_of(inputs.back(), columns));
  }
  check_agreement(inputs, facts);

  // The row key: the resume key less the provenance columns (shards on other machines differ there).
  std::vector<size_t> key_columns;
  std::set<std::string> provenance_columns;
  for (const auto& c : provenance_schema()) provenance_columns.insert(c.name);
  for (size_t i = 0; i < experiment_schema().size(); ++i)
    if (experiment_schema()[i].key && !provenance_columns.count(experiment_schema()[i].name)) key_columns.push_back(i);
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

BoundCommand bind_merge(CLI::App& parent) {
  auto o = std::make_shared<MergeOptions>();
  CLI::App* cmd = parent.add_subcommand(
      "merge", "join the CSV files of a sharded table or sweep (--shard I/N) into the file one process would write");
  cmd->add_option("--out", o->out, "merged CSV file to write")->required();
  cmd->add_option("inputs", o->inputs, "the shards' CSV files (each shard's finished --out)")->required();
  cmd->add_flag("--force", o->force, "replace an existing --out");
  return {cmd, [o](const Provenance& provenance) { return run_merge(*o, provenance); }};
}

}  // namespace raycoh
