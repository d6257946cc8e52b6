#include "records/merge_files.h"

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
#include "records/quality_row.h"
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

// The value of option `name` in a command's words ("--name v" or "--name=v"), or `fallback`.
std::string option_value(const std::vector<std::string>& words, const std::string& name, const std::string& fallback) {
  for (size_t i = 0; i < words.size(); ++i) {
    if (words[i] == name && i + 1 < words.size()) return words[i + 1];
    if (words[i].rfind(name + "=", 0) == 0) return words[i].substr(name.size() + 1);
  }
  return fallback;
}

CsvLayout converge_layout() { return csv_layout(converge_schema()); }
CsvLayout converge_summary_layout() { return csv_layout(summary_schema()); }

namespace merge_detail {

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

void refuse_partial(const std::string& path) {
  if (path.size() > 8 && path.compare(path.size() - 8, 8, ".partial") == 0)
    throw Error(
        fmt::format("merge: {} is an unfinished run's file; run that shard's command again (it resumes and "
                    "finishes it), then merge its --out",
                    path));
}

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
  for (const Kind& k : csv_kinds()) {
    const std::vector<std::string>& want = k.layout.columns;
    if (fields.size() < want.size() && std::equal(fields.begin(), fields.end(), want.begin()))
      throw Error(
          fmt::format("merge: {}: a {} CSV of an older version: it lacks the column '{}' (and every later "
                      "one) that this build writes; merge files written by one build",
                      path, k.name, want[fields.size()]));
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
      if (fields.size() < columns.size() && std::equal(fields.begin(), fields.end(), columns.begin()))
        throw Error(
            fmt::format("merge: {}: a {} CSV of an older version: it lacks the column '{}' (and every "
                        "later one) that this build writes; merge files written by one build",
                        path, kind.name, columns[fields.size()]));
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

RunFacts facts_of(const Input& in, const Kind& kind, const MergeCommands& commands) {
  const std::vector<std::string>& columns = kind.layout.columns;
  RunFacts f;
  f.frames = commands.experiment_frames;
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
      if (name == "tracer_params") v = ResultKey{row[column_index(columns, "tracer")], "", "", "", v}.label(true);
      if (name == "reference") v = std::filesystem::path(v).filename().string();  // caches may be node-local
      per_scene[row[scene]].insert(v);
    }
    for (const auto& [sc, v] : per_scene) f.fields.emplace_back(name + " of " + sc, joined(v));
  }
  std::set<std::string> command_lines, shards;
  for (const auto& row : in.rows) {
    const std::vector<std::string> words = command_words(row[column_index(columns, "command_line")]);
    // A tune's speed stage (an experiment file) measures --speed-frames frames; its --frames are the renders'.
    const bool tune = !words.empty() && words.front() == "tune";
    if (f.words.empty()) f.words = words;
    if (tune && f.command.empty() && command_lines.empty()) f.frames = commands.tune_speed_frames;
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
        const std::string frames_option = tune ? "--speed-frames" : "--frames";
        if (w == frames_option && i + 1 < words.size()) f.frames = std::atoi(words[i + 1].c_str());
        if (w.rfind(frames_option + "=", 0) == 0) f.frames = std::atoi(w.c_str() + frames_option.size() + 1);
        command += (command.empty() ? "" : " ") + w;
      }
    }
    command_lines.insert(command);
    shards.insert(shard);
  }
  if (shards.size() > 1)
    throw Error(fmt::format("merge: {} holds rows of several shards ({}); merge each shard's own --out", in.path,
                            joined(shards)));
  if (!shards.empty()) f.shard = parse_shard(in.path + ": --shard", *shards.begin());
  f.command = joined(command_lines);
  return f;
}

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

Shards read_shards(const std::vector<std::string>& paths, const Kind& kind, const MergeCommands& commands) {
  Shards s;
  for (const std::string& path : paths) {
    s.inputs.push_back(read_input(path, kind));
    s.facts.push_back(facts_of(s.inputs.back(), kind, commands));
  }
  check_agreement(s.inputs, s.facts);
  for (const RunFacts& f : s.facts)
    if (!f.empty && !s.any) {
      s.any = &f;
      s.count = f.shard.count;
    }
  return s;
}

}  // namespace merge_detail

}  // namespace raycoh
