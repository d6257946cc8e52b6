// Helpers of the command-line tests (cli_*_test.cpp): line counts, lines, expected one-line errors.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "records/csv.h"
#include "records/provenance.h"
#include "tests/test_util.h"

namespace raycoh::test {

inline std::vector<std::string> read_lines(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(in, line)) lines.push_back(line);
  return lines;
}

// Rows of a CSV file as column -> text (rows whose field count differs from the header's are skipped).
inline std::vector<std::map<std::string, std::string>> read_rows(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> header, fields;
  std::vector<std::map<std::string, std::string>> rows;
  if (!std::getline(in, line) || !csv_parse_line(line, header)) return rows;
  while (std::getline(in, line)) {
    if (!csv_parse_line(line, fields) || fields.size() != header.size()) continue;
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < header.size(); ++i) row[header[i]] = fields[i];
    rows.push_back(std::move(row));
  }
  return rows;
}

inline int count_lines(const std::filesystem::path& p) { return static_cast<int>(read_lines(p).size()); }

// The command fails with `code`, one line on stderr that contains `must_contain`.
inline void expect_error(const std::string& args, const std::string& must_contain, int code = 2) {
  const CommandResult r = run_raycoh(args);
  EXPECT_EQ(r.exit_code, code) << args << "\n" << r.output;
  EXPECT_NE(r.output.find(must_contain), std::string::npos) << args << "\n" << r.output;
  EXPECT_NE(r.output.find("error"), std::string::npos) << r.output;
}

// `row` (a CSV row this build's raycoh wrote) with its git_revision column replaced by `revision`. The row is
// found by its revision and build type, both this build's: Release, RelWithDebInfo (scripts/sanitize) or any other.
inline std::string with_git_revision(const std::string& row, const std::string& revision) {
  const Provenance p = collect_provenance(0, nullptr, 1);
  const std::string fields = "," + p.git_revision + "," + p.build_type + ",";
  const size_t at = row.find(fields);
  if (at == std::string::npos) {
    ADD_FAILURE() << "no '" << fields << "' in " << row;
    return row;
  }
  return row.substr(0, at + 1) + revision + row.substr(at + 1 + p.git_revision.size());
}

}  // namespace raycoh::test
