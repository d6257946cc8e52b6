// The rendering commands (`render`, `quality`, `converge`, `compare`) from the command line.
#include <gtest/gtest.h>

#include "tests/cli_util.h"

namespace raycoh::test {
namespace {

TEST(CliRendering, RenderingCommandsCheckTheirInputs) {
  expect_error("render --res 0x8", "--res");
  expect_error("render --generator nope", "valid generators");
  expect_error("render --out img.tiff --res 8x8 --frames 1", "img.tiff");
  expect_error("render --crop 0,0,100,100 --res 8x8 --frames 1 --out /tmp/raycoh_crop.pfm", "--crop");
  expect_error("quality --frames 0", "--frames");
  expect_error("quality --exposure -1", "--exposure");
  expect_error("converge --time -5s", "--time");
  expect_error("converge --time 0", "--time");
  expect_error("compare /no/such.exr /no/other.exr", "/no/such.exr");
  const auto out = temp_dir("cli_render") / "r.pfm";
  const CommandResult r = run_raycoh("render --scene cornell --res 16x12 --frames 2 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(std::filesystem::exists(out));
}

TEST(CliRendering, QualityResumesFinishedRowsAndConvergeWritesItsSummary) {
  const auto dir = temp_dir("cli_quality");
  const auto out = dir / "q.csv";
  const std::string args =
      "quality --scenes cornell --generators noopt,ours --frames 1 --ref-frames 2 "
      "--bias-renders 2 --res 16x12 --cache " +
      (dir / "cache").string() + " --out " + out.string();
  CommandResult r = run_raycoh(args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("| generator | cornell |"), std::string::npos) << r.output;
  const auto complete = read_lines(out);
  ASSERT_EQ(complete.size(), 3u);
  std::filesystem::remove(out);
  write_file(out.string() + ".partial", complete[0] + "\n" + complete[1] + "\n");
  r = run_raycoh(args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("resuming: 1 rows"), std::string::npos) << r.output;
  const auto resumed = read_lines(out);
  ASSERT_EQ(resumed.size(), 3u);
  EXPECT_EQ(resumed[1], complete[1]);

  const auto conv = dir / "c.csv";
  r = run_raycoh("converge --generators noopt,ours --time 100s --max-frames 2 --ref-frames 2 --res 16x12 --cache " +
                 (dir / "cache").string() + " --out " + conv.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(count_lines(conv), 1 + 2 * 2);
  EXPECT_EQ(count_lines(dir / "c-summary.csv"), 1 + 3);  // ours on wall, trace and modeled_gpu
}

}  // namespace
}  // namespace raycoh::test
