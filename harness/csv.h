// CSV output that never loses what was measured: rows go to "<path>.partial", each written whole and flushed;
// finish() renames the file to <path>. A run that stops early leaves its rows in the .partial file, and the
// next run with the same columns resumes from it: resumed_rows() are the complete rows found there (a torn
// last line is dropped), and new rows are appended after them.
#pragma once

#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace raycoh {

class CsvWriter {
 public:
  CsvWriter() = default;
  enum class Resume { Yes, No };
  // Opens <path>.partial: with Resume::Yes, resumes it when it exists with exactly these columns; otherwise
  // starts it with the header. Throws raycoh::Error if the file cannot be written.
  // A non-empty comment (Resume::No only) is written first as "# comment" lines, before the header.
  CsvWriter(const std::string& path, const std::vector<std::string>& columns, Resume resume = Resume::Yes,
            const std::string& comment = "");
  // Throws WriteError (harness/exit_codes.h) when the row cannot be written and flushed.
  void write_row(const std::vector<std::string>& values);
  // Renames <path>.partial to <path>; throws WriteError when closing or renaming fails.
  void finish();
  // Keeps only the resumed rows `keep` accepts, rewriting <path>.partial without the others; returns how many
  // were dropped.
  template <class Pred>
  size_t keep_resumed_if(Pred keep) {
    std::vector<std::vector<std::string>> kept;
    for (auto& row : resumed_)
      if (keep(row)) kept.push_back(std::move(row));
    const size_t dropped = resumed_.size() - kept.size();
    resumed_ = std::move(kept);
    if (dropped > 0) rewrite_partial();
    return dropped;
  }
  // Removes <path>.partial if no row was ever written to it (nothing measured, nothing resumed).
  void discard_if_empty();
  bool is_open() const { return out_.is_open(); }
  const std::string& path() const { return path_; }
  std::string partial_path() const { return path_ + ".partial"; }
  size_t rows() const { return rows_; }  // rows written by this run
  const std::vector<std::vector<std::string>>& resumed_rows() const { return resumed_; }
  const std::vector<std::string>& columns() const { return columns_; }
  // Index of a column name; throws an invariant failure for unknown names.
  size_t column(const std::string& name) const;

 private:
  void rewrite_partial();
  static std::string csv_line(const std::vector<std::string>& fields);
  void put(const std::string& text);  // writes and flushes; throws WriteError on failure
  std::string path_;
  std::ofstream out_;
  std::vector<std::string> columns_;
  std::vector<std::vector<std::string>> resumed_;
  size_t rows_ = 0;
};

std::string csv_escape(const std::string& field);
// Parses one CSV record (RFC 4180 quoting, no embedded newlines). Returns false on unbalanced quotes.
bool csv_parse_line(const std::string& line, std::vector<std::string>& fields);

}  // namespace raycoh
