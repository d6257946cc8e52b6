#include "harness/csv.h"

#include <algorithm>
#include <filesystem>
#include <fmt/format.h>

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
    if (allow_resume == Resume::Yes && in && std::getline(in, line) && !in.eof() && csv_parse_line(line, fields) && fields == columns) {
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
    if (!comment.empty()) out_ << "# " << comment << '\n';
    for (size_t i = 0; i < columns.size(); ++i) out_ << (i ? "," : "") << csv_escape(columns[i]);
    out_ << '\n';
    out_.flush();
  }
}

size_t CsvWriter::column(const std::string& name) const {
  const auto it = std::find(columns_.begin(), columns_.end(), name);
  RAYCOH_CHECK(it != columns_.end(), "unknown CSV column " + name);
  return static_cast<size_t>(it - columns_.begin());
}

void CsvWriter::write_row(const std::vector<std::string>& values) {
  RAYCOH_CHECK(values.size() == columns_.size(), fmt::format("{} values for {} columns", values.size(), columns_.size()));
  // One string, one write: a crash leaves at most one torn line, which a resume drops.
  std::string line;
  for (size_t i = 0; i < values.size(); ++i) line += (i ? "," : "") + csv_escape(values[i]);
  line += '\n';
  out_ << line;
  out_.flush();
  ++rows_;
}

void CsvWriter::rewrite_partial() {
  out_.close();
  out_.open(partial_path(), std::ios::out | std::ios::trunc);
  if (!out_) throw Error(fmt::format("--out {}: cannot write {}", path_, partial_path()));
  std::string text;
  for (size_t i = 0; i < columns_.size(); ++i) text += (i ? "," : "") + csv_escape(columns_[i]);
  text += '\n';
  for (const auto& row : resumed_) {
    for (size_t i = 0; i < row.size(); ++i) text += (i ? "," : "") + csv_escape(row[i]);
    text += '\n';
  }
  out_ << text;
  out_.flush();
}

void CsvWriter::finish() {
  out_.close();
  std::error_code ec;
  std::filesystem::rename(partial_path(), path_, ec);
  if (ec) throw Error(fmt::format("--out {}: cannot rename {}: {}", path_, partial_path(), ec.message()));
}

void CsvWriter::discard_if_empty() {
  if (rows_ > 0 || !resumed_.empty()) return;
  out_.close();
  std::error_code ec;
  std::filesystem::remove(partial_path(), ec);
}

}  // namespace raycoh
