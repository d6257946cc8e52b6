#include "harness/merge.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>

#include "core/durable_file.h"
#include "core/error.h"
#include "harness/cli.h"
#include "harness/command.h"
#include "records/csv.h"
#include "harness/experiment.h"
#include "records/experiment_row.h"
#include "harness/quality.h"
#include "records/quality_row.h"
#include "harness/render_common.h"
#include "records/shard.h"

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

// What merge knows of one kind of CSV: its columns, the fields every file of one run agrees on, and a row's key.
enum class KindId { Experiment, Quality, Converge, ConvergeSummary };
struct Kind {
  KindId id;
  std::string name;
  CsvLayout layout;
  std::vector<std::string> run_fields;    // equal in every file of one run
  std::string scene_column;               // per scene (this column's value) ...
  std::vector<std::string> scene_fields;  // ... these are equal in every file
  std::vector<std::string> key;           // a row's identity within one run
};

// The resume key less the provenance columns (shards on other machines differ there).
template <class Row>
std::vector<std::string> key_less_provenance(const Schema<Row>& schema) {
  std::set<std::string> provenance_columns;
  for (const auto& c : provenance_schema()) provenance_columns.insert(c.name);
  std::vector<std::string> key;
  for (const auto& c : schema)
    if (c.key && !provenance_columns.count(c.name)) key.push_back(c.name);
  return key;
}

const std::vector<Kind>& csv_kinds() {
  static const std::vector<Kind> all = [] {
    const std::vector<std::string> build = {"git_revision", "build_type", "compiler", "embree_version"};
    const auto with = [&](std::vector<std::string> more) {
      std::vector<std::string> v = build;
      v.insert(v.end(), more.begin(), more.end());
      return v;
    };
    return std::vector<Kind>{
        {KindId::Experiment,
         "table/sweep",
         csv_layout(experiment_schema()),
         with({"width", "height", "seed"}),
         "scene",
         {"scene_fingerprint", "tracer_params"},
         key_less_provenance(experiment_schema())},
        {KindId::Quality,
         "quality",
         csv_layout(quality_schema()),
         with({"width", "height", "seed", "frames", "ref_frames", "bias_renders", "max_depth", "rr_depth", "tone_map",
               "tracer_spec", "reference_kind"}),
         "scene_spec",
         {"scene_fingerprint", "tracer_params", "reference", "exposure"},
         key_less_provenance(quality_schema())},
        {KindId::Converge,
         "converge",
         converge_layout(),
         with({"width", "height", "seed", "ref_frames", "max_depth", "rr_depth", "tone_map"}),
         "scene_spec",
         {"scene_fingerprint", "tracer_params", "reference"},
         {"scene_spec", "method", "frame"}},
        {KindId::ConvergeSummary,
         "converge summary",
         converge_summary_layout(),
         build,
         "scene",
         {},
         {"scene", "method", "baseline", "metric", "clock"}},
    };
  }();
  return all;
}

// One input file: its rows as written (fields untouched) and what the checks need of them.
struct Input {
  std::string path;
  std::vector<std::vector<std::string>> rows;
  std::vector<size_t> lines;  // the line of each row
};

void refuse_partial(const std::string& path) {
  if (path.size() > 8 && path.compare(path.size() - 8, 8, ".partial") == 0)
    throw Error(
        fmt::format("merge: {} is an unfinished run's file; run that shard's command again (it resumes and "
                    "finishes it), then merge its --out",
                    path));
}

// The kind of CSV `path` is, from its header.
const Kind& kind_of_file(const std::string& path) {
  refuse_partial(path);
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::vector<std::string> fields;
  if (!in || !std::getline(in, line)) throw Error(fmt::format("merge: {}: cannot read the file, or it is empty", path));
  if (!line.empty() && line.back() == '\r') line.pop_back();
  csv_parse_line(line, fields);
  for (const Kind& k : csv_kinds())
    if (fields == k.layout.columns) {
      if (k.id == KindId::ConvergeSummary)
        throw Error(
            fmt::format("merge: {} is a converge summary; name the shards' per-frame CSV files (their "
                        "-summary.csv files are merged with them)",
                        path));
      return k;
    }
  throw Error(
      fmt::format("merge: {}: its columns are not those of this build's table/sweep, quality or converge CSV ({} "
                  "columns); merge files written by one build",
                  path, fields.size()));
}

Input read_input(const std::string& path, const Kind& kind) {
  refuse_partial(path);
  const std::vector<std::string>& columns = kind.layout.columns;
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
            fmt::format("merge: {}: its columns are not those of this build's {} CSV (first "
                        "header: {} columns, expected {}); merge files written by one build",
                        path, kind.name, fields.size(), columns.size()));
      continue;
    }
    try {
      kind.layout.check_row(fields);
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
  std::string command;                                      // the command line less --shard, --out, --force, ...
  std::vector<std::string> words;                           // a row's command line as words, whole
  int frames = ExperimentOptions{}.frames;
  bool empty = false;  // no rows (a shard that owned no unit): nothing to agree on, its shard unknown
};

RunFacts facts_of(const Input& in, const Kind& kind) {
  const std::vector<std::string>& columns = kind.layout.columns;
  RunFacts f;
  f.empty = in.rows.empty();
  for (const std::string& name : kind.run_fields) {
    std::set<std::string> values;
    for (const auto& row : in.rows) values.insert(row[column_index(columns, name)]);
    f.fields.emplace_back(name, joined(values));
  }
  // Per scene: e.g. its fingerprint and its tracers' parameters.
  const size_t scene = column_index(columns, kind.scene_column);
  for (const std::string& name : kind.scene_fields) {
    std::map<std::string, std::set<std::string>> per_scene;
    const size_t c = column_index(columns, name);
    for (const auto& row : in.rows) {
      std::string v = row[c];
      if (name == "tracer_params") v = row[column_index(columns, "tracer")] + "[" + v + "]";
      if (name == "reference") v = std::filesystem::path(v).filename().string();  // caches may be node-local
      per_scene[row[scene]].insert(v);
    }
    for (const auto& [sc, v] : per_scene) f.fields.emplace_back(name + " of " + sc, joined(v));
  }
  std::set<std::string> commands, shards;
  for (const auto& row : in.rows) {
    const std::vector<std::string> words = command_words(row[column_index(columns, "command_line")]);
    if (f.words.empty()) f.words = words;
    std::string command, shard = "0/1";
    for (size_t i = 0; i < words.size(); ++i) {
      const std::string& w = words[i];
      // Where a shard writes and finds things, not what it measures.
      const bool place = w == "--out" || w == "--images" || w == "--cache";
      if ((w == "--shard" || place) && i + 1 < words.size()) {
        if (w == "--shard") shard = words[i + 1];
        ++i;
      } else if (w.rfind("--shard=", 0) == 0) {
        shard = w.substr(8);
      } else if (w.rfind("--out=", 0) == 0 || w.rfind("--images=", 0) == 0 || w.rfind("--cache=", 0) == 0 ||
                 w == "--force") {
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
            fmt::format("merge: {} and {} disagree on the parameters (command line without --shard, --out, "
                        "--images, --cache and --force): '{}' vs '{}'; shards of one run must agree",
                        inputs[a].path, inputs[b].path, facts[a].command, facts[b].command));
      if (facts[a].shard.count != facts[b].shard.count)
        throw Error(fmt::format("merge: {} and {} disagree on the shard count: {} vs {}", inputs[a].path,
                                inputs[b].path, facts[a].shard.text(), facts[b].shard.text()));
    }
}

// Inputs that are not there (a shard that failed or is still running), listed together.
void refuse_absent(const std::vector<std::string>& paths, const std::string& out) {
  std::error_code ec;
  std::vector<std::string> absent;
  for (const std::string& path : paths) {
    if (std::filesystem::exists(path, ec)) continue;
    const std::string partial = path + ".partial";
    absent.push_back(
        std::filesystem::exists(partial, ec)
            ? fmt::format("{} (unfinished: {} holds {} row(s); run that shard's command again, it resumes)", path,
                          partial, std::max<int>(0, count_lines(partial) - 1))
            : fmt::format("{} (no such file)", path));
  }
  if (!absent.empty())
    throw Error(fmt::format("merge: not writing {}: {} of {} input(s) missing: {}", out, absent.size(), paths.size(),
                            join(absent, "; ")));
}

void refuse_same_files(const std::vector<std::string>& inputs, const std::vector<std::string>& outs) {
  std::error_code ec;
  for (size_t i = 0; i < inputs.size(); ++i) {
    for (const std::string& out : outs)
      if (std::filesystem::equivalent(inputs[i], out, ec))
        throw Error(fmt::format("merge: --out {} is one of the inputs; write the merged file elsewhere", out));
    for (size_t j = 0; j < i; ++j)
      if (std::filesystem::equivalent(inputs[i], inputs[j], ec))
        throw Error(fmt::format("merge: {} and {} are the same file; name each shard once", inputs[j], inputs[i]));
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

// The value of option `name` in a command's words ("--name v" or "--name=v"), or `fallback`.
std::string option_value(const std::vector<std::string>& words, const std::string& name, const std::string& fallback) {
  for (size_t i = 0; i < words.size(); ++i) {
    if (words[i] == name && i + 1 < words.size()) return words[i + 1];
    if (words[i].rfind(name + "=", 0) == 0) return words[i].substr(name.size() + 1);
  }
  return fallback;
}

// quality and converge: the run's scene x generator units, in the order one process renders them, read from the
// command line every row records (the shards dealt these same units).
struct RunUnits {
  std::vector<std::string> scenes, methods;
  std::vector<std::string> keys;  // render_unit(scene, method), scene-major
};

RunUnits units_of(const Kind& kind, const std::string& file, const std::vector<std::string>& words) {
  RunUnits u;
  std::vector<PluginSpec> generators;
  try {
    if (kind.id == KindId::Quality) {
      u.scenes = split_scenes("--scenes", option_value(words, "--scenes", join(QualityOptions{}.scenes, ",")));
      generators =
          split_nonempty("--generators", option_value(words, "--generators", join_specs(QualityOptions{}.generators)));
    } else {
      u.scenes = {option_value(words, "--scene", ConvergeOptions{}.scene)};
      generators =
          split_nonempty("--generators", option_value(words, "--generators", join_specs(ConvergeOptions{}.generators)));
    }
  } catch (const Error& e) {
    throw Error(fmt::format("merge: {}: the command line its rows record cannot be read: {}", file, e.what()));
  }
  for (const PluginSpec& g : generators) u.methods.push_back(g.text());
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

// Reads and checks the inputs of one kind: files, agreement, shard count.
struct Shards {
  std::vector<Input> inputs;
  std::vector<RunFacts> facts;
  int count = 1;
  const RunFacts* any = nullptr;  // a file's facts that has rows
};

Shards read_shards(const std::vector<std::string>& paths, const Kind& kind) {
  Shards s;
  for (const std::string& path : paths) {
    s.inputs.push_back(read_input(path, kind));
    s.facts.push_back(facts_of(s.inputs.back(), kind));
  }
  check_agreement(s.inputs, s.facts);
  for (const RunFacts& f : s.facts)
    if (!f.empty && !s.any) {
      s.any = &f;
      s.count = f.shard.count;
    }
  return s;
}

// quality and converge (with its summaries): the shards' rows joined, or every problem named at once.
int merge_units(const MergeOptions& o, const Kind& kind) {
  const bool converge = kind.id == KindId::Converge;
  std::vector<std::string> summary_paths;
  const std::string summary_out = stem_path(o.out) + "-summary.csv";
  if (converge) {
    for (const std::string& in : o.inputs) summary_paths.push_back(stem_path(in) + "-summary.csv");
    refuse_absent(summary_paths, summary_out);
    refuse_same_files(summary_paths, {o.out, summary_out});
  }
  const Shards shards = read_shards(o.inputs, kind);
  if (!shards.any) throw Error(fmt::format("merge: not writing {}: no input holds a row", o.out));
  const RunUnits units = units_of(kind, shards.inputs[0].path, shards.any->words);
  Joined rows = join_units(kind, shards.inputs, shards.facts, units, shards.count);
  Shards summaries;
  Joined summary_rows;
  if (converge) {
    summaries = read_shards(summary_paths, csv_kinds()[static_cast<size_t>(KindId::ConvergeSummary)]);
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

}  // namespace

int run_merge(const MergeOptions& o, const Provenance& provenance) {
  (void)provenance;
  if (o.inputs.empty()) throw Error("merge: no input files; name the shards' CSV files after --out OUT");
  check_output_file("--out", o.out);
  refuse_same_files(o.inputs, {o.out});
  refuse_absent(o.inputs, o.out);
  const Kind& kind = kind_of_file(o.inputs[0]);
  if (kind.id != KindId::Experiment) return merge_units(o, kind);
  const Shards shards = read_shards(o.inputs, kind);
  return merge_experiment(o, kind, shards.inputs, shards.facts);
}

BoundCommand bind_merge(CLI::App& parent) {
  auto o = std::make_shared<MergeOptions>();
  CLI::App* cmd = parent.add_subcommand(
      "merge",
      "join the CSV files of a sharded table, sweep, quality or converge (--shard I/N) into what one process writes");
  cmd->add_option("--out", o->out, "merged CSV file to write")->required();
  cmd->add_option("inputs", o->inputs, "the shards' CSV files (each shard's finished --out)")->required();
  cmd->add_flag("--force", o->force, "replace an existing --out");
  return {cmd, [o](const Provenance& provenance) { return run_merge(*o, provenance); }};
}

}  // namespace raycoh
