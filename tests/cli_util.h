// Helpers of the command-line tests (cli_*_test.cpp): line counts, lines, expected one-line errors.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

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
