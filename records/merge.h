// `raycoh merge --out OUT IN...` (the results layer's merge; the command's options are harness/merge.cpp's): joins the
// CSV files of a sharded `table`, `sweep`, `quality` or `converge` run
// (--shard I/N, each shard's finished --out; for converge also each one's <stem>-summary.csv, joined into
// <OUT stem>-summary.csv) into the files a single process would have written. The kind is read from the header.
//
// Refused, one line naming the files and the field (exit 2), before anything is written:
// - files that disagree where the shards of one run must agree: git_revision, build_type, compiler,
//   embree_version, the run's settings columns (width, height, seed; quality and converge also frames, reference
//   frames, depths, tone map, ...), per scene its scene_fingerprint and tracer_params (quality and converge also
//   the reference's file name, which holds the digest of its cache key), and the command line without --shard,
//   --out, --images, --cache and --force (every other option: scenes, methods, tracers, frames, repeat, threads);
// - files of different shard counts; inputs that do not exist (listed together, each with the rows its
//   <file>.partial holds when the shard is unfinished: run its command again, it resumes) and .partial inputs;
// - an incomplete or doubled result: shards none of the files holds, missing rows (with the shard that owes each)
//   and rows whose key is in two places. table/sweep: the product scene x frame x row kind the rows show, the key
//   the resume key less the provenance columns, the owing shard from the deal of the units the rows show.
//   quality/converge: the scene x generator units of the command line the rows record (--scenes/--scene,
//   --generators, or their defaults), dealt as the shards dealt them; quality one row per unit, converge the
//   frames 1 .. n of every unit and, in the summary, every clock for each unit but the baseline.
//   Nothing is written then: never a short file that looks whole.
// Rows keep every field as the shard wrote it (timings as measured, host and cpu per row). table/sweep rows are
// ordered by scene, frame, then the order the shards wrote them in, which is the single process's order wherever
// the shards show it; quality and converge rows in one process's order (scene, generator; converge: frame, then
// generator). OUT is written whole or not at all (core/durable_file.h); an existing OUT is refused unless --force.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "records/provenance.h"
#include "records/schema.h"

namespace raycoh {

// What merge needs of one kind of CSV: its columns and a check of one row's fields (throws
// std::invalid_argument naming the column).
struct CsvLayout {
  std::vector<std::string> columns;
  std::function<void(const std::vector<std::string>&)> check_row;
};
template <class Row>
CsvLayout csv_layout(const Schema<Row>& schema) {
  return {column_names(schema), [&schema](const std::vector<std::string>& fields) { read_row(schema, fields); }};
}
// converge's per-frame and summary CSVs (records/converge_row.h).
CsvLayout converge_layout();
CsvLayout converge_summary_layout();

// quality and converge: the run's scene x generator units, in the order one process renders them, read from the
// command line every row records (the shards dealt these same units).
struct RunUnits {
  std::vector<std::string> scenes, methods;
  std::vector<std::string> keys;  // render_unit(scene, method), scene-major
};

// What merge needs of the commands whose files it joins (the command, harness/merge.cpp, fills it in): the frames a
// table or sweep renders without --frames, and the scenes and methods a quality (quality = true) or converge
// command line names, with the command's defaults for options it does not give (throws raycoh::Error for words it
// cannot read).
struct MergeCommands {
  int experiment_frames = 1;
  int tune_speed_frames = 1;  // the frames of a tune's speed stage without --speed-frames
  std::function<RunUnits(bool quality, const std::vector<std::string>& words)> units;
};

struct MergeOptions {
  std::vector<std::string> inputs;
  std::string out;
  bool force = false;
  MergeCommands commands;
};
int run_merge(const MergeOptions& options, const Provenance& provenance);

// A row's command line (provenance column, shell-quoted words) as words; the program name is left out.
std::vector<std::string> command_words(const std::string& command_line);
// The value of option `name` in a command's words ("--name v" or "--name=v"), or `fallback`.
std::string option_value(const std::vector<std::string>& words, const std::string& name, const std::string& fallback);

}  // namespace raycoh
