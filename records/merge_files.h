// The parts of `raycoh merge` (records/merge.h) shared by its files: the kinds of CSV it joins, the input files read
// and checked (merge_files.cpp), the table/sweep join (merge_table.cpp), the quality/converge join (merge_units.cpp).
#pragma once

#include <set>
#include <string>
#include <utility>
#include <vector>

#include "records/merge.h"
#include "records/shard.h"

namespace raycoh::merge_detail {

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

const std::vector<Kind>& csv_kinds();

// One input file: its rows as written (fields untouched) and what the checks need of them.
struct Input {
  std::string path;
  std::vector<std::vector<std::string>> rows;
  std::vector<size_t> lines;  // the line of each row
};

// The kind of CSV `path` is, from its header.
const Kind& kind_of_file(const std::string& path);
Input read_input(const std::string& path, const Kind& kind);
int count_lines(const std::string& path);
size_t column_index(const std::vector<std::string>& columns, const std::string& name);
std::string joined(const std::set<std::string>& values);

// What a file says about the run it belongs to; two shards of one run agree on every entry.
struct RunFacts {
  std::vector<std::pair<std::string, std::string>> fields;  // field name -> values ("a|b" when several)
  Shard shard;                                              // from the rows' command lines
  std::string command;                                      // the command line less --shard, --out, --force, ...
  std::vector<std::string> words;                           // a row's command line as words, whole
  int frames = 0;                                           // --frames, else the command's default
  bool empty = false;  // no rows (a shard that owned no unit): nothing to agree on, its shard unknown
};

RunFacts facts_of(const Input& in, const Kind& kind, const MergeCommands& commands);
// Every run-wide field equal in every file; the first difference is the error.
void check_agreement(const std::vector<Input>& inputs, const std::vector<RunFacts>& facts);
// Inputs that are not there (a shard that failed or is still running), listed together.
void refuse_absent(const std::vector<std::string>& paths, const std::string& out);
void refuse_same_files(const std::vector<std::string>& inputs, const std::vector<std::string>& outs);

// Reads and checks the inputs of one kind: files, agreement, shard count.
struct Shards {
  std::vector<Input> inputs;
  std::vector<RunFacts> facts;
  int count = 1;
  const RunFacts* any = nullptr;  // a file's facts that has rows
};

Shards read_shards(const std::vector<std::string>& paths, const Kind& kind, const MergeCommands& commands);

// A total order of the items that keeps the order of every sequence wherever the sequences agree (Kahn's
// algorithm over "a came right before b" edges, ties by first appearance): each shard's rows are a subsequence
// of the single process's order, so the merged order is that order wherever the shards show it.
// Items starting with `lead` come first among the ready ones (the primary pass opens every frame).
std::vector<std::string> merged_order(const std::vector<std::vector<std::string>>& sequences,
                                      const std::string& lead = "");
std::string list_head(const std::vector<std::string>& items, size_t shown = 3);
std::string row_key(const std::vector<std::string>& row, const std::vector<size_t>& key_columns);
std::vector<size_t> column_indices(const std::vector<std::string>& columns, const std::vector<std::string>& names);
std::vector<std::string> hosts_of(const std::vector<const std::vector<std::string>*>& rows,
                                  const std::vector<std::string>& columns);

int merge_experiment(const MergeOptions& o, const Kind& kind, const std::vector<Input>& inputs,
                     const std::vector<RunFacts>& facts);
// quality and converge (with its summaries): the shards' rows joined, or every problem named at once.
int merge_units(const MergeOptions& o, const Kind& kind);

}  // namespace raycoh::merge_detail
