#include "records/csv.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace raycoh {

std::string csv_escape(const std::string& field) {
  if (field.find_first_of(",\"\n\r") == std::string::npos) return field;
  std::string out = "\"";
  for (char c : field) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

bool csv_parse_line(const std::string& line, std::vector<std::string>& fields) {
  fields.clear();
  std::string cur;
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cur += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        cur += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.push_back(std::move(cur));
      cur.clear();
    } else {
      cur += c;
    }
  }
  fields.push_back(std::move(cur));
  return !quoted;
}

namespace {

struct Line {
  size_t number = 0;  // 1-based, as an editor shows it
  std::string text;   // without the newline and a trailing '\r'
  bool terminated = true, had_cr = false;
};

std::vector<Line> split_lines(const std::string& bytes) {
  std::vector<Line> lines;
  size_t start = 0;
  while (start < bytes.size()) {
    const size_t nl = bytes.find('\n', start);
    Line l;
    l.number = lines.size() + 1;
    l.terminated = nl != std::string::npos;
    l.text = bytes.substr(start, (l.terminated ? nl : bytes.size()) - start);
    if (!l.text.empty() && l.text.back() == '\r') {
      l.text.pop_back();
      l.had_cr = true;
    }
    start = l.terminated ? nl + 1 : bytes.size();
    lines.push_back(std::move(l));
  }
  return lines;
}

std::string read_all(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) throw Error(fmt::format("{}: cannot read {}", what, path));
  return text.str();
}

std::string quoted_list(const std::set<std::string>& values) {
  std::string out;
  size_t shown = 0;
  for (const std::string& v : values) {
    if (shown++ == 4) return out + ", ...";
    out += (out.empty() ? "'" : ", '") + v + "'";
  }
  return out;
}

std::string first_column_difference(const std::vector<std::string>& found, const std::vector<std::string>& want) {
  if (found.size() < want.size() && std::equal(found.begin(), found.end(), want.begin()))
    return fmt::format(
        "it lacks the column '{}'{} that this version writes after them (written by an older version)",
        want[found.size()],
        want.size() - found.size() > 1 ? fmt::format(" and {} more", want.size() - found.size() - 1) : std::string());
  for (size_t i = 0; i < std::max(found.size(), want.size()); ++i) {
    const std::string f = i < found.size() ? found[i] : "(none)", w = i < want.size() ? want[i] : "(none)";
    if (f != w) return fmt::format("column {} is '{}', this version writes '{}'", i + 1, f, w);
  }
  return "same columns";
}

// Why a line of an earlier run cannot be resumed ("" when it is a row of `column_count` fields, parsed into
// `fields`, whose values `o.check_values` accepts).
std::string why_not_a_row(const Line& l, size_t column_count, const CsvWriter::Options& o,
                          std::vector<std::string>& fields) {
  if (!l.terminated) return "torn last line (a write was interrupted)";
  if (l.text.empty()) return "empty line";
  if (l.text.find('\0') != std::string::npos) return "NUL byte in the line";
  if (!csv_parse_line(l.text, fields)) return "unbalanced quotes";
  if (fields.size() != column_count) return fmt::format("{} fields for {} columns", fields.size(), column_count);
  if (o.check_values) return o.check_values(fields);
  return "";
}

// The lines of `source` that are not resumed, each after a comment saying why, appended to `rejected_path` and
// synced; the first ten are named on stderr.
void keep_aside(const std::string& source, const std::vector<std::pair<const Line*, std::string>>& rejected,
                const std::string& rejected_path) {
  std::string kept_aside;
  for (size_t i = 0; i < rejected.size(); ++i) {
    const auto& [l, why] = rejected[i];
    kept_aside += fmt::format("# {} line {}: {}\n", source, l->number, why) + l->text + "\n";
    if (i < 10) std::fprintf(stderr, "resume: %s line %zu skipped: %s\n", source.c_str(), l->number, why.c_str());
  }
  if (rejected.size() > 10) std::fprintf(stderr, "resume: ... %zu lines skipped in all\n", rejected.size());
  std::fprintf(stderr, "resume: the skipped lines are copied to %s; their rows are measured again\n",
               rejected_path.c_str());
  const int fd = ::open(rejected_path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) throw WriteError(fmt::format("{}: cannot create: {}", rejected_path, strerror(errno)));
  try {
    write_all(fd, kept_aside, rejected_path);
    sync_file(fd, rejected_path);
  } catch (...) {
    ::close(fd);
    throw;
  }
  ::close(fd);
}

}  // namespace

CsvWriter::CsvWriter(const std::string& path, const std::vector<std::string>& columns, const Options& o)
    : path_(path), columns_(columns) {
  RAYCOH_CHECK(o.comment.empty() || o.resume == Resume::No, "a commented CSV cannot be resumed");
  check_output_file("--out", path);
  lock_ = OutputLock(path, "--out " + path);
  std::error_code ec;
  const bool had_partial = std::filesystem::exists(partial_path(), ec);
  if (o.force) {
    if (had_partial || std::filesystem::exists(path_, ec))
      std::fprintf(stderr, "--force: starting afresh; %s is replaced when this run finishes\n", path_.c_str());
  } else if (o.resume == Resume::Yes) {
    read_earlier_run(o);
  } else {
    refuse_existing(o);
    if (already_complete_) {
      lock_.release();
      return;
    }
    if (had_partial)
      std::fprintf(stderr, "discarding %s: an interrupted run of this command is measured again from the start\n",
                   partial_path().c_str());
  }
  if (!resumed_.empty() || from_finished_file_) {
    // read_earlier_run left a clean <path>.partial holding exactly the header and the resumed rows.
    fd_ = ::open(partial_path().c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
    if (fd_ < 0) throw WriteError(fmt::format("--out {}: cannot open {}: {}", path_, partial_path(), strerror(errno)));
  } else {
    fd_ = ::open(partial_path().c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0)
      throw WriteError(fmt::format("--out {}: cannot create {}: {}", path_, partial_path(), strerror(errno)));
    std::string head;
    if (!o.comment.empty()) head = "# " + o.comment + '\n';
    put(head + csv_line(columns_));
  }
  set_interrupt_hint(
      o.resume == Resume::Yes
          ? fmt::format("rows measured so far are kept in {}; run the same command again to resume", partial_path())
          : fmt::format("{} is left as it was; this command starts again when run again", path_));
}

// Rows of an interrupted (<path>.partial) or finished (<path>) run; see the header.
void CsvWriter::read_earlier_run(const Options& o) {
  std::error_code ec;
  std::string source = partial_path();
  if (!std::filesystem::exists(source, ec)) {
    if (!std::filesystem::exists(path_, ec)) return;
    source = path_;
  }
  const std::vector<Line> lines = split_lines(read_all(source, "--out " + path_));
  if (lines.empty()) return;  // an empty file: nothing to resume
  std::vector<std::string> fields;
  if (!csv_parse_line(lines[0].text, fields) || fields != columns_)
    throw Error(fmt::format(
        "--out {}: {} has other columns than this version of raycoh writes ({}); pass --force to replace it, or "
        "choose another --out",
        path_, source, first_column_difference(fields, columns_)));

  std::vector<std::pair<size_t, std::set<std::string>>> rule;
  for (const auto& [name, values] : o.rule.columns) rule.emplace_back(column(name), values);
  std::vector<std::pair<const Line*, std::string>> rejected;  // line, why
  bool rewrite = lines[0].had_cr || !lines[0].terminated;
  for (size_t i = 1; i < lines.size(); ++i) {
    const Line& l = lines[i];
    const std::string why = why_not_a_row(l, columns_.size(), o, fields);
    if (!why.empty()) {
      rejected.emplace_back(&l, why);
      continue;
    }
    for (const auto& [col, values] : rule)
      if (!values.count(fields[col]))
        throw Error(fmt::format(
            "--out {}: {} line {} was measured with other parameters: its {} is '{}', this run's {} {}; pass "
            "--force to replace the file, or choose another --out",
            path_, source, l.number, columns_[col], fields[col], values.size() == 1 ? "is" : "are one of",
            quoted_list(values)));
    rewrite = rewrite || l.had_cr;
    resumed_.push_back(fields);
  }

  if (!rejected.empty()) {
    keep_aside(source, rejected, rejected_path());
    rewrite = true;
  }
  from_finished_file_ = source == path_ && !rewrite;
  if (source == path_ || rewrite) {
    std::string text = csv_line(columns_);
    for (const auto& row : resumed_) text += csv_line(row);
    write_file_atomically(partial_path(), text);
  }
  if (!resumed_.empty() && source == path_)
    std::fprintf(stderr, "%s holds %zu finished rows: only rows it lacks are measured\n", path_.c_str(),
                 resumed_.size());
}

void CsvWriter::refuse_existing(const Options& o) {
  std::error_code ec;
  if (!std::filesystem::exists(path_, ec)) return;
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> fields;
  bool header = true;
  for (const Line& l : split_lines(read_all(path_, "--out " + path_))) {
    if (l.text.rfind("#", 0) == 0) continue;
    if (!csv_parse_line(l.text, fields)) continue;
    if (header) {
      header = false;
      if (fields != columns_) break;
      continue;
    }
    if (fields.size() == columns_.size()) rows.push_back(fields);
  }
  bool same = !rows.empty() && !o.same_run.empty();
  for (const auto& [name, value] : o.same_run)
    for (const auto& row : rows) same = same && row[column(name)] == value;
  if (same) {
    already_complete_ = true;
    return;
  }
  throw Error(
      fmt::format("--out {} already holds a finished run ({} rows); pass --force to replace it (the file is replaced "
                  "only when the new run finishes), or choose another --out",
                  path_, rows.size()));
}

std::string CsvWriter::csv_line(const std::vector<std::string>& fields) {
  std::string line;
  for (size_t i = 0; i < fields.size(); ++i) line += (i ? "," : "") + csv_escape(fields[i]);
  return line + '\n';
}

void CsvWriter::put(const std::string& text) {
  const off_t before = ::lseek(fd_, 0, SEEK_END);
  try {
    write_all(fd_, text, fmt::format("--out {}: writing {} failed", path_, partial_path()));
  } catch (const WriteError& e) {
    if (before >= 0 && ::ftruncate(fd_, before) != 0) {
      // The torn line stays; a resume skips it.
    }
    throw WriteError(
        fmt::format("{} ({} rows before it are kept there, whole; free space and run the same command "
                    "again)",
                    e.what(), rows_ + resumed_.size()));
  }
}

size_t CsvWriter::column(const std::string& name) const {
  const auto it = std::find(columns_.begin(), columns_.end(), name);
  RAYCOH_CHECK(it != columns_.end(), "unknown CSV column " + name);
  return static_cast<size_t>(it - columns_.begin());
}

void CsvWriter::write_row(const std::vector<std::string>& values) {
  RAYCOH_CHECK(values.size() == columns_.size(),
               fmt::format("{} values for {} columns", values.size(), columns_.size()));
  RAYCOH_CHECK(fd_ >= 0, "write_row on a closed CSV");
  // One string, one write: a crash leaves at most one torn line, which a resume skips.
  put(csv_line(values));
  ++rows_;
}

void CsvWriter::finish() {
  if (already_complete_ || finished_) return;
  RAYCOH_CHECK(fd_ >= 0, "finish on a closed CSV");
  std::error_code ec;
  if (from_finished_file_ && rows_ == 0) {  // nothing new: the finished file stays exactly as it was
    ::close(fd_);
    fd_ = -1;
    std::filesystem::remove(partial_path(), ec);
  } else {
    sync_file(fd_, "--out " + path_ + ": " + partial_path());
    const int rc = ::close(fd_);
    fd_ = -1;
    if (rc != 0)
      throw WriteError(fmt::format("--out {}: closing {} failed: {} (its rows are kept there)", path_, partial_path(),
                                   strerror(errno)));
    std::filesystem::rename(partial_path(), path_, ec);
    if (ec)
      throw WriteError(fmt::format("--out {}: cannot rename {} to it: {} (the rows are kept in {})", path_,
                                   partial_path(), ec.message(), partial_path()));
    sync_parent_folder(path_);
  }
  finished_ = true;
  set_interrupt_hint("");
  lock_.release();
}

void CsvWriter::discard_if_empty() {
  if (rows_ > 0 || (!resumed_.empty() && !from_finished_file_) || finished_) return;
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  std::error_code ec;
  std::filesystem::remove(partial_path(), ec);
}

CsvWriter::~CsvWriter() {
  if (!finished_ && !already_complete_ && !path_.empty()) {
    discard_if_empty();
    set_interrupt_hint("");
  }
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace raycoh
