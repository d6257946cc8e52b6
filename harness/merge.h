// `raycoh merge --out OUT IN...`: joins the CSV files of a sharded `table` or `sweep` run (--shard I/N, each
// shard's finished --out) into the one file a single process would have written.
//
// Refused, one line naming the files and the field (exit 2), before anything is written:
// - files that disagree where the shards of one run must agree: git_revision, build_type, compiler,
//   embree_version, width, height, seed, a scene's scene_fingerprint or tracer_params, and the command line
//   without --shard, --out and --force (every other option: scenes, methods, tracers, frames, repeat, threads);
// - files of different shard counts; inputs that do not exist (listed together, each with the rows its
//   <file>.partial holds when the shard is unfinished: run its command again, it resumes) and .partial inputs;
// - an incomplete or doubled result: shards none of the files holds, rows missing from the product scene x frame x
//   row kind (with the shard that owes each), and rows whose key (the resume key less the provenance columns)
//   is in two places. The shard owing a missing row is found by dealing the units the rows show (harness/shard.h).
//   Nothing is written then: never a short file that looks whole.
// Rows keep every field as the shard wrote it (timings as measured, host and cpu per row). Rows are ordered by
// scene, frame, then the order the shards wrote them in, which is the single process's order wherever the
// shards show it. OUT is written whole or not at all (core/durable_file.h); an existing OUT is refused unless
// --force.
#pragma once

#include <string>
#include <vector>

#include "harness/provenance.h"

namespace raycoh {

struct MergeOptions {
  std::vector<std::string> inputs;
  std::string out;
  bool force = false;
};
int run_merge(const MergeOptions& options, const Provenance& provenance);

// A row's command line (provenance column, shell-quoted words) as words; the program name is left out.
std::vector<std::string> command_words(const std::string& command_line);

}  // namespace raycoh
