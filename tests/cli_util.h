// Helpers of the command-line tests (cli_*_test.cpp): line counts, lines, expected one-line errors.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

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

}  // namespace raycoh::test
