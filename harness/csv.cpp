#include "harness/csv.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

#include "core/error.h"
#include "harness/exit_codes.h"

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

CsvWriter::CsvWriter(const std::string& path, const std::vector<std::string>& columns, Resume allow_resume,
                     const std::string& comment)
    : path_(path), columns_(columns) {
  RAYCOH_CHECK(comment.empty() || allow_resume == Resume::No, "a commented CSV cannot be resumed");
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);

  // Resume: keep the complete rows of an interrupted run with the same columns.
  bool resume = false;
  size_t keep_bytes = 0;
  {
    std::ifstream in(partial_path(), std::ios::binary);
    std::string line;
    std::vector<std::string> fields;
    if (allow_resume == Resume::Yes && in && std::getline(in, line) && !in.eof() && csv_parse_line(line, fields) &&
        fields == columns) {
      resume = true;
      keep_bytes = line.size() + 1;
      while (std::getline(in, line)) {
        if (in.eof()) break;  // no newline: a torn last row
        if (!csv_parse_line(line, fields) || fields.size() != columns.size()) break;
        resumed_.push_back(fields);
        keep_bytes += line.size() + 1;
      }
    }
  }
  if (resume) {
    std::filesystem::resize_file(partial_path(), keep_bytes, ec);
    out_.open(partial_path(), std::ios::out | std::ios::app);
  } else {
    out_.open(partial_path(), std::ios::out | std::ios::trunc);
  }
  if (!out_) throw Error(fmt::format("--out {}: cannot write {}", path, partial_path()));
  if (!resume) {
    std::string head;
    if (!comment.empty()) head = "# " + comment + '\n';
    put(head + csv_line(columns));
  }
}

std::string CsvWriter::csv_line(const std::vector<std::string>& fields) {
  std::string line;
  for (size_t i = 0; i < fields.size(); ++i) line += (i ? "," : "") + csv_escape(fields[i]);
  return line + '\n';
}

void CsvWriter::put(const std::string& text) {
  out_ << text;
  out_.flush();
  if (!out_)
    throw WriteError(fmt::format("--out {}: writing {} failed (disk full or file removed?)", path_, partial_path()));
}

size_t CsvWriter::column(const std::string& name) const {
  const auto it = std::find(columns_.begin(), columns_.end(), name);
  RAYCOH_CHECK(it != columns_.end(), "unknown CSV column " + name);
  return static_cast<size_t>(it - columns_.begin());
}

void CsvWriter::write_row(const std::vector<std::string>& values) {
  RAYCOH_CHECK(values.size() == columns_.size(),
               fmt::format("{} values for {} columns", values.size(), columns_.size()));
  // One string, one write: a crash leaves at most one torn line, which a resume drops.
  put(csv_line(values));
  ++rows_;
}

void CsvWriter::rewrite_partial() {
  out_.close();
  out_.open(partial_path(), std::ios::out | std::ios::trunc);
  if (!out_) throw WriteError(fmt::format("--out {}: cannot rewrite {}", path_, partial_path()));
  std::string text = csv_line(columns_);
  for (const auto& row : resumed_) text += csv_line(row);
  put(text);
}

void CsvWriter::finish() {
  out_.close();
  if (out_.fail()) throw WriteError(fmt::format("--out {}: closing {} failed", path_, partial_path()));
  std::error_code ec;
  std::filesystem::rename(partial_path(), path_, ec);
  if (ec) throw WriteError(fmt::format("--out {}: cannot rename {}: {}", path_, partial_path(), ec.message()));
}

void CsvWriter::discard_if_empty() {
  if (rows_ > 0 || !resumed_.empty()) return;
  out_.close();
  std::error_code ec;
  std::filesystem::remove(partial_path(), ec);
}

}  // namespace raycoh
