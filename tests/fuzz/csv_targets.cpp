// Fuzz targets of the CSV readers: an earlier run's rows read back for resume (records/csv.cpp through
// record_csv.h, the table/sweep schema), and the shard files `raycoh merge` joins (records/merge.h).
#include <string>
#include <vector>

#include "harness/merge_defaults.h"
#include "records/experiment_row.h"
#include "records/merge.h"
#include "records/provenance.h"
#include "records/record_csv.h"
#include "tests/fuzz/fuzz_targets.h"
#include "tests/fuzz/fuzz_util.h"

namespace raycoh::fuzz {

// First byte even: the rest is a finished run's run.csv, odd: an interrupted run's run.csv.partial. The rows are
// read back with the table/sweep schema and no rule on their values (every well-formed row is this run's, so the
// checks of the rows' values are reached), then written back and renamed as a resumed run finishes.
void fuzz_csv_resume(const uint8_t* data, size_t size) {
  if (size < 1) return;
  clear_scratch();
  const std::string path = scratch_dir() + "/run.csv";
  write_scratch(data[0] % 2 == 0 ? "run.csv" : "run.csv.partial",
                std::string(reinterpret_cast<const char*>(data) + 1, size - 1));
  expect_clean("run.csv", [&] {
    RecordCsv<ExperimentRow> csv(path, experiment_schema(), CsvWriter::Options::resumable(false, ResumeRule{}));
    csv.finish();
  });
}

// Input: up to four files split by fuzz_util.h's separator: shard0.csv, shard1.csv (the inputs) and, for a converge
// run, shard0-summary.csv, shard1-summary.csv. Merged into merged.csv.
void fuzz_shard_merge(const uint8_t* data, size_t size) {
  static const Provenance provenance = collect_provenance(0, nullptr, 1);
  clear_scratch();
  const std::vector<std::string> parts = split_input(data, size, 4);
  const char* names[] = {"shard0.csv", "shard1.csv", "shard0-summary.csv", "shard1-summary.csv"};
  MergeOptions o;
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string path = write_scratch(names[i], parts[i]);
    if (i < 2) o.inputs.push_back(path);
  }
  o.out = scratch_dir() + "/merged.csv";
  o.force = true;
  o.commands = merge_command_defaults();
  expect_clean("", [&] { run_merge(o, provenance); });
}

}  // namespace raycoh::fuzz
