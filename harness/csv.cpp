#include "harness/csv.h"

#include <cstdio>
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

CsvWriter::CsvWriter(const std::string& path, const std::vector<std::string>& columns)
    : path_(path), columns_(columns.size()) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  out_.open(partial_path(), std::ios::out | std::ios::trunc);
  if (!out_) throw Error(fmt::format("--out {}: cannot write {}", path, partial_path()));
  write_row(columns);
  rows_ = 0;
}

void CsvWriter::write_row(const std::vector<std::string>& values) {
  RAYCOH_CHECK(values.size() == columns_, fmt::format("{} values for {} columns", values.size(), columns_));
  for (size_t i = 0; i < values.size(); ++i) out_ << (i ? "," : "") << csv_escape(values[i]);
  out_ << '\n';
  out_.flush();
  ++rows_;
}

void CsvWriter::finish() {
  out_.close();
  std::error_code ec;
  std::filesystem::rename(partial_path(), path_, ec);
  if (ec) throw Error(fmt::format("--out {}: cannot rename {}: {}", path_, partial_path(), ec.message()));
}

}  // namespace raycoh
