// Provenance that identifies the run (records/provenance.h): every row names its machine beyond the host name;
// rows run under a profiler or sanitizer say so (run_under) and the report leaves them out as timings; rows the CPU
// measured carry no GPU columns.
#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "tests/cli_util.h"
#include "tests/test_util.h"

namespace raycoh::test {
namespace {

TEST(Provenance, RowsNameTheirMachineAndWhatTheyRanUnder) {
  const auto dir = temp_dir("provenance");
  const std::string args = "table --scenes cornell --generators noopt,ours --tracers cpu --res 32x24 --frames 1 ";
  const std::string plain = (dir / "plain.csv").string(), profiled = (dir / "profiled.csv").string();
  ASSERT_EQ(run_raycoh(args + "--out " + plain).exit_code, 0);
  const CommandResult r = run_shell("RAYCOH_RUN_UNDER=ncu $R " + args + "--out " + profiled);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const auto& row : read_rows(plain)) {
    EXPECT_TRUE(std::regex_match(row.at("machine"), std::regex(".+-[0-9a-f]{8}"))) << row.at("machine");
    EXPECT_EQ(row.at("machine").rfind(row.at("host") + "-", 0), 0u) << row.at("machine");
    EXPECT_EQ(row.at("run_under"), "");
    for (const char* gpu : {"gpu_sms", "gpu_driver", "cuda_runtime", "gpu_sm_mhz_start", "gpu_mem_mhz_end"})
      EXPECT_EQ(row.at(gpu), "") << gpu;
  }
  const auto rows = read_rows(profiled);
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& row : rows) EXPECT_EQ(row.at("run_under"), "ncu");
  // The report reads the plain file's speeds and leaves the profiled rows out, saying why.
  const CommandResult rep = run_raycoh("report " + plain + " " + profiled + " --out " + (dir / "r.html").string());
  ASSERT_EQ(rep.exit_code, 0) << rep.output;
  std::string md;
  for (const std::string& line : read_lines(dir / "r.md")) md += line + "\n";
  EXPECT_NE(md.find(profiled + ": 3 row(s) run under ncu left out"), std::string::npos) << md;
  EXPECT_NE(md.find("## Table 1 layout: " + plain), std::string::npos) << md;
  EXPECT_EQ(md.find("## Table 1 layout: " + profiled), std::string::npos) << md;
}

}  // namespace
}  // namespace raycoh::test
