// CSV output that never loses what was measured and never passes off a damaged or foreign file as a result.
//
// Rows go to "<path>.partial", each written whole with one checked write; finish() fsyncs it, renames it to <path>
// and fsyncs the folder. A lock ("<path>.lock", core/durable_file.h) keeps a second run off the same output.
//
// Resume (Resume::Yes): the rows of an earlier run are read back from <path>.partial (an interrupted run) or, when
// there is none, from <path> itself (a finished run, so the same command finds its rows and measures only what
// is missing). Every line is checked on its own: an empty, torn, NUL-holding, unbalanced or short line, or a value
// its column cannot hold, is skipped with a warning naming its line and copied to "<path>.rejected", and every
// other row is kept. A file with other columns, or rows measured with other parameters (the command's
// ResumeRule), is refused with the reason: raycoh::Error naming the field, unless `force` discards it.
// Resume::No (one timed measurement: a convergence curve, a ray dump): an existing <path> is refused unless
// `force`, or reported complete when the command that wrote it was the same (same_run).
#pragma once

#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/durable_file.h"

namespace raycoh {

// What rows of an earlier run must hold to belong to this one: per column, the values this run writes.
struct ResumeRule {
  std::vector<std::pair<std::string, std::set<std::string>>> columns;
  ResumeRule& require(const std::string& column, std::set<std::string> values) {
    columns.emplace_back(column, std::move(values));
    return *this;
  }
};

class CsvWriter {
 public:
  enum class Resume { Yes, No };
  struct Options {
    Resume resume = Resume::Yes;
    bool force = false;   // --force: start afresh, whatever <path> and <path>.partial hold
    std::string comment;  // Resume::No only: written first as "# comment" lines, before the header
    // Resume::Yes: "" when a row's values parse, else why not (names the column).
    std::function<std::string(const std::vector<std::string>&)> check_values;
    ResumeRule rule;  // Resume::Yes: rows outside it are another run's
    // Resume::No: column values that mark this very command (its command line and code revision): an existing
    // <path> whose every row holds them is this command's finished result.
    std::vector<std::pair<std::string, std::string>> same_run;

    // A resumable CSV (table, sweep, quality) whose earlier rows must meet `rule`.
    static Options resumable(bool force, ResumeRule rule) {
      Options o;
      o.force = force;
      o.rule = std::move(rule);
      return o;
    }
    // A CSV written in one go (a convergence curve, a ray dump, a comparison).
    static Options once(bool force, std::vector<std::pair<std::string, std::string>> same_run = {},
                        std::string comment = "") {
      Options o;
      o.resume = Resume::No;
      o.force = force;
      o.same_run = std::move(same_run);
      o.comment = std::move(comment);
      return o;
    }
  };

  CsvWriter() = default;
  // Checks the path, takes the lock, reads back an earlier run's rows, opens <path>.partial. Throws raycoh::Error
  // (the user's input) or WriteError.
  CsvWriter(const std::string& path, const std::vector<std::string>& columns, const Options& options);
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;
  // An unfinished writer removes a .partial that holds no row; the lock is released.
  ~CsvWriter();

  // Throws WriteError when the row cannot be written (the .partial keeps every earlier row, whole).
  void write_row(const std::vector<std::string>& values);
  // Syncs and renames <path>.partial to <path>. When nothing was measured and the rows came from a finished
  // <path>, that file is left exactly as it was. Throws WriteError.
  void finish();
  // Removes <path>.partial if no row was ever written to it (nothing measured, nothing resumed).
  void discard_if_empty();
  // Resume::No with same_run: <path> already holds this command's finished result; nothing was opened.
  bool already_complete() const { return already_complete_; }
  const std::string& path() const { return path_; }
  std::string partial_path() const { return path_ + ".partial"; }
  std::string rejected_path() const { return path_ + ".rejected"; }
  size_t rows() const { return rows_; }  // rows written by this run
  const std::vector<std::vector<std::string>>& resumed_rows() const { return resumed_; }
  const std::vector<std::string>& columns() const { return columns_; }
  // Index of a column name; throws an invariant failure for unknown names.
  size_t column(const std::string& name) const;

 private:
  void read_earlier_run(const Options& o);
  void refuse_existing(const Options& o);
  void open_partial(bool fresh, const std::string& comment);
  static std::string csv_line(const std::vector<std::string>& fields);
  void put(const std::string& text);  // one checked write; a failed one is cut back off the file
  std::string path_;
  OutputLock lock_;
  int fd_ = -1;
  bool finished_ = false, already_complete_ = false;
  bool from_finished_file_ = false;  // resumed rows came from <path>, which is still intact
  std::vector<std::string> columns_;
  std::vector<std::vector<std::string>> resumed_;
  size_t rows_ = 0;
};

std::string csv_escape(const std::string& field);
// Parses one CSV record (RFC 4180 quoting, no embedded newlines). Returns false on unbalanced quotes.
bool csv_parse_line(const std::string& line, std::vector<std::string>& fields);

}  // namespace raycoh
