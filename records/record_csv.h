// A CSV of records: CsvWriter (records/csv.h) driven by a column schema (records/schema.h). Rows of an earlier run
// are read back into records once, here; a row whose value its column cannot hold is skipped by CsvWriter with a
// warning naming file, line and column.
#pragma once

#include <fmt/format.h>

#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "records/csv.h"
#include "records/provenance.h"
#include "records/schema.h"

namespace raycoh {

// The rule every command's earlier rows must meet besides its own settings: the same code revision and build,
// and the same machine and thread count (timings of another CPU or thread count are not this run's).
inline ResumeRule& require_provenance(ResumeRule& rule, const Provenance& p) {
  return rule.require("git_revision", {p.git_revision})
      .require("build_type", {p.build_type})
      .require("cpu", {p.cpu})
      .require("threads", {std::to_string(p.threads)});
}

// Resume::No outputs: an existing file written by the same command line at the same revision is complete.
inline std::vector<std::pair<std::string, std::string>> same_command(const Provenance& p) {
  return {{"command_line", p.command_line}, {"git_revision", p.git_revision}};
}

template <class Row>
class RecordCsv {
 public:
  RecordCsv(const std::string& path, const Schema<Row>& schema, CsvWriter::Options options)
      : schema_(schema), csv_(path, column_names(schema), with_value_check(std::move(options), schema)) {
    for (const auto& text : csv_.resumed_rows()) resumed_.push_back(read_row(schema_, text));
  }

  void write(const Row& row) { csv_.write_row(write_row(schema_, row)); }
  void finish() { csv_.finish(); }
  void discard_if_empty() { csv_.discard_if_empty(); }
  bool already_complete() const { return csv_.already_complete(); }
  const std::vector<Row>& resumed() const { return resumed_; }
  size_t rows() const { return csv_.rows(); }
  std::string partial_path() const { return csv_.partial_path(); }
  const Schema<Row>& schema() const { return schema_; }

  // Called from the handler of `e`, which stopped a run: drops an empty <path>.partial and rethrows `e`, or throws
  // it again saying how many rows the partial file keeps and that the same command resumes them.
  // Rethrows e (a DeviceFault as a DeviceFault), prefixed by `where` (the unit being measured, "" for none) and
  // saying how many rows are kept and that the same command resumes.
  [[noreturn]] void rethrow_keeping_rows(const Error& e, const std::string& where = "") {
    csv_.discard_if_empty();
    const size_t kept = rows() + resumed_.size();
    const std::string what = where.empty() ? e.what() : where + ": " + e.what();
    const std::string msg =
        kept == 0 ? what
                  : fmt::format("{} ({} rows measured so far are kept in {}; run the same command again to resume)",
                                what, kept, partial_path());
    if (dynamic_cast<const DeviceFault*>(&e)) throw DeviceFault(msg);
    if (kept == 0 && where.empty()) throw;
    throw Error(msg);
  }

 private:
  static CsvWriter::Options with_value_check(CsvWriter::Options o, const Schema<Row>& schema) {
    o.check_values = [&schema](const std::vector<std::string>& fields) -> std::string {
      try {
        read_row(schema, fields);
        return "";
      } catch (const std::invalid_argument& e) {
        return e.what();
      }
    };
    return o;
  }

  const Schema<Row>& schema_;
  CsvWriter csv_;
  std::vector<Row> resumed_;
};

}  // namespace raycoh
