// A CSV of records: CsvWriter (harness/csv.h) driven by a column schema (harness/schema.h). Resumed rows are read
// back into records once, here; a value its column cannot hold is a DamagedFileError naming file, line and column.
#pragma once

#include <fmt/format.h>

#include <string>
#include <vector>

#include "core/error.h"
#include "harness/csv.h"
#include "harness/exit_codes.h"
#include "harness/schema.h"

namespace raycoh {

template <class Row>
class RecordCsv {
 public:
  RecordCsv(const std::string& path, const Schema<Row>& schema, CsvWriter::Resume resume = CsvWriter::Resume::Yes,
            const std::string& comment = "")
      : schema_(schema), csv_(path, column_names(schema), resume, comment) {
    const auto& text = csv_.resumed_rows();
    for (size_t i = 0; i < text.size(); ++i) {
      try {
        resumed_.push_back(read_row(schema_, text[i]));
      } catch (const std::invalid_argument& e) {
        throw DamagedFileError(fmt::format("{} line {}: {}; delete the file or fix the line to resume",
                                           csv_.partial_path(), i + 2, e.what()));
      }
    }
  }

  void write(const Row& row) { csv_.write_row(write_row(schema_, row)); }
  void finish() { csv_.finish(); }
  void discard_if_empty() { csv_.discard_if_empty(); }
  const std::vector<Row>& resumed() const { return resumed_; }
  size_t rows() const { return csv_.rows(); }
  std::string partial_path() const { return csv_.partial_path(); }
  const Schema<Row>& schema() const { return schema_; }

  // Called from the handler of `e`, which stopped a run: drops an empty <path>.partial and rethrows `e`, or throws
  // it again saying how many rows the partial file keeps and that the same command resumes them.
  [[noreturn]] void rethrow_keeping_rows(const Error& e) {
    csv_.discard_if_empty();
    const size_t kept = rows() + resumed_.size();
    if (kept == 0) throw;
    throw Error(fmt::format("{} ({} rows measured so far are kept in {}; run the same command again to resume)",
                            e.what(), kept, partial_path()));
  }

  // Keeps only the resumed records `keep` accepts (rewriting <path>.partial); returns how many were dropped.
  template <class Pred>
  size_t keep_resumed_if(Pred keep) {
    std::vector<bool> kept;
    std::vector<Row> rows;
    for (Row& r : resumed_) {
      kept.push_back(keep(r));
      if (kept.back()) rows.push_back(std::move(r));
    }
    resumed_ = std::move(rows);
    size_t i = 0;
    return csv_.keep_resumed_if([&](const std::vector<std::string>&) { return kept[i++]; });
  }

 private:
  const Schema<Row>& schema_;
  CsvWriter csv_;
  std::vector<Row> resumed_;
};

}  // namespace raycoh
