// Results are never lost or silently wrong, from the command line: a full disk (a file size limit here; a real
// tiny tmpfs in scripts/fault-injection), reruns of finished commands, two runs on one --out, Ctrl-C, threads,
// late path checks, memory, duplicate list entries. Exit codes are only 0, 1, 2 or 128 + a signal.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "shading/image.h"
#include "tests/cli_util.h"

namespace raycoh::test {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

int one_line_errors(const std::string& output) {
  int n = 0;
  for (size_t at = output.find("raycoh: "); at != std::string::npos; at = output.find("raycoh: ", at + 1)) ++n;
  return n;
}

void expect_no_leftovers(const fs::path& dir) {
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    EXPECT_EQ(name.find(".tmp"), std::string::npos) << name;
    EXPECT_NE(e.path().extension(), ".lock") << name;
  }
}

// Shell: waits (up to 60 s) until <out>.partial holds at least `rows` rows.
std::string wait_for_rows(const fs::path& out, int rows) {
  return "for i in $(seq 600); do [ \"$(cat '" + out.string() + ".partial' 2>/dev/null | wc -l)\" -gt " +
         std::to_string(rows) + " ] && break; sleep 0.1; done;";
}

TEST(CliSafety, ARerunOfAFinishedTableMeasuresNothingAndOtherParametersAreRefused) {
  const auto out = temp_dir("safety_rerun") / "t.csv";
  const std::string args =
      "table --scenes cornell --generators noopt --res 24x16 --frames 2 --repeat 1 --tracers cpu --out " + out.string();
  ASSERT_EQ(run_raycoh(args).exit_code, 0);
  const std::string finished = slurp(out);
  CommandResult r = run_raycoh(args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("already held every row of this run: nothing was measured"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("| noopt |"), std::string::npos) << "the tables are printed from the finished rows";
  EXPECT_EQ(slurp(out), finished);

  // More frames extend the file; other settings are refused, naming the field.
  r = run_raycoh("table --scenes cornell --generators noopt --res 24x16 --frames 3 --repeat 1 --tracers cpu --out " +
                 out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(count_lines(out), 1 + 3 * 2);
  EXPECT_EQ(slurp(out).rfind(finished, 0), 0u) << "the finished rows stay first, as measured";
  const std::string other =
      "table --scenes cornell --generators noopt --res 32x16 --frames 2 --repeat 1 --tracers cpu --out " + out.string();
  r = run_raycoh(other);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("its width is '24', this run's is '32'; pass --force"), std::string::npos) << r.output;
  EXPECT_EQ(one_line_errors(r.output), 1) << r.output;
  r = run_raycoh("--threads 7 " + args);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("its threads is"), std::string::npos) << r.output;
  r = run_raycoh(other + " --force");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(count_lines(out), 1 + 2 * 2);
  EXPECT_NE(slurp(out).find(",32,16,"), std::string::npos);
  expect_no_leftovers(out.parent_path());
}

TEST(CliSafety, AFullDiskKeepsEveryWholeRowAndTheRerunCompletesIt) {
  const auto dir = temp_dir("safety_full");
  const auto out = dir / "t.csv";
  const std::string args =
      "table --scenes cornell --generators noopt --res 24x16 --frames 30 --repeat 1 --tracers cpu --out " +
      out.string();
  CommandResult r = run_shell("ulimit -f 24; $R " + args);  // 24 KiB: a disk that fills after ~15 rows
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("error: write failed: --out " + out.string() + ": writing " + out.string() +
                          ".partial failed: File too large"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("Wrote"), std::string::npos) << r.output;
  EXPECT_EQ(one_line_errors(r.output), 1) << r.output;
  EXPECT_FALSE(fs::exists(out));
  const std::string kept = slurp(out.string() + ".partial");
  ASSERT_FALSE(kept.empty());
  EXPECT_EQ(kept.back(), '\n') << "the row that did not fit was cut back off";
  const int rows_kept = count_lines(out.string() + ".partial") - 1;
  EXPECT_GT(rows_kept, 5);
  expect_no_leftovers(dir);

  r = run_raycoh(args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("resuming: " + std::to_string(rows_kept) + " rows"), std::string::npos) << r.output;
  EXPECT_EQ(count_lines(out), 1 + 30 * 2);
}

TEST(CliSafety, ImagesAndReferencesOnAFullDiskFailWholeAndLeaveNoTempFile) {
  const auto dir = temp_dir("safety_full_images");
  for (const char* ext : {".png", ".exr", ".pfm"}) {
    if (std::string(ext) != ".pfm" && !image_io_available()) continue;  // refused up front there
    const auto img = dir / (std::string("r") + ext);
    const CommandResult r =
        run_shell("ulimit -f 8; $R render --scene cornell --res 200x150 --frames 1 --out " + img.string());
    EXPECT_EQ(r.exit_code, 1) << ext << r.output;
    EXPECT_NE(r.output.find("error: write failed: " + img.string()), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(img)) << ext;
  }
  const CommandResult r = run_shell(
      "ulimit -f 8; $R converge --scene cornell --res 200x150 --time 0.2s --ref-frames 2 "
      "--cache " +
      (dir / "cache").string() + " --out " + (dir / "c.csv").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(one_line_errors(r.output), 1) << r.output;
  expect_no_leftovers(dir);
}

TEST(CliSafety, ASecondRunOnTheSameOutSaysWhoHoldsItAndTheFirstFinishesWhole) {
  const auto dir = temp_dir("safety_lock");
  const auto out = dir / "t.csv";
  const std::string args =
      "table --scenes voxels --generators noopt --res 160x120 --frames 200 --repeat 3 --tracers cpu --out " +
      out.string();
  // The second run starts once the first has written rows.
  const CommandResult r = run_shell("$R " + args + " >/dev/null 2>&1 & first=$!; " + wait_for_rows(out, 4) + " $R " +
                                    args + "; echo second=$?; wait $first; echo first=$?");
  EXPECT_NE(r.output.find("is being written by another run (pid"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("second=2"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("first=0"), std::string::npos) << r.output;
  EXPECT_EQ(count_lines(out), 1 + 200 * 2);  // no duplicate, no torn line
  expect_no_leftovers(dir);
}

TEST(CliSafety, CtrlCSaysHowToResumeAndTheRerunResumes) {
  const auto dir = temp_dir("safety_sigint");
  const auto out = dir / "t.csv";
  const std::string args =
      "table --scenes voxels --generators noopt --res 160x120 --frames 200 --repeat 3 --tracers cpu --out " +
      out.string();
  CommandResult r =
      // env --default-signal: a background job of sh ignores SIGINT; the terminal's foreground job does not.
      run_shell("env --default-signal=INT $R " + args + " & pid=$!; " + wait_for_rows(out, 10) +
                " kill -INT $pid; wait $pid; echo status=$?");
  EXPECT_NE(r.output.find("raycoh: interrupted: rows measured so far are kept in " + out.string() +
                          ".partial; run the same command again to resume"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("status=130"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out.string() + ".lock"));
  const int kept = count_lines(out.string() + ".partial") - 1;
  ASSERT_GT(kept, 0);
  r = run_raycoh(args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("resuming: "), std::string::npos) << r.output;
  EXPECT_EQ(count_lines(out), 1 + 200 * 2);
}

TEST(CliSafety, ASigintIgnoredFromTheStartStaysIgnored) {
  // A background job of a non-interactive shell ignores SIGINT, so that the terminal's Ctrl-C does not end it.
  const auto dir = temp_dir("safety_sigign");
  const auto out = dir / "t.csv";
  const std::string args =
      "table --scenes voxels --generators noopt --res 160x120 --frames 40 --repeat 3 --tracers cpu --out " +
      out.string();
  const CommandResult r = run_shell("(trap '' INT; exec $R " + args + ") >/dev/null 2>&1 & pid=$!; " +
                                    wait_for_rows(out, 2) + " kill -INT $pid; wait $pid; echo status=$?");
  EXPECT_NE(r.output.find("status=0"), std::string::npos) << r.output;
  EXPECT_EQ(count_lines(out), 1 + 40 * 2);
}

TEST(CliSafety, BadPathsDuplicatesAndTooLargeRunsAreRefusedBeforeAnyWork) {
  const auto dir = temp_dir("safety_input");
  write_file(dir / "afile", "x");
  const std::string out = " --out " + (dir / "o.csv").string();
  expect_error("table --res 8x8 --out " + dir.string(), "is a folder");
  expect_error("quality --res 16x16 --cache " + (dir / "afile").string() + out,
               "--cache " + (dir / "afile").string() + ": is a file");
  expect_error("quality --res 16x16 --images " + (dir / "afile").string() + out, "--images");
  expect_error("converge --res 16x16 --cache " + (dir / "afile").string() + out, "is a file, not a folder");
  expect_error("table --scenes cornell,cornell --res 8x8" + out, "'cornell' is listed twice");
  expect_error("table --generators noopt,ours,noopt --res 8x8" + out, "'noopt' is listed twice");
  expect_error("table --encoders none,origin,origin --res 8x8" + out, "'origin' is listed twice");
  expect_error("sweep --scene cornell --tiles 8x8,8x8 --res 8x8" + out, "'8x8' is listed twice");
  expect_error("quality --generators ours,ours --res 16x16" + out, "'ours' is listed twice");
  expect_error("render --res 16x16 --crop 0,0,4,4 --crop 0,0,4,4 --out " + (dir / "r.exr").string(), "given twice");
  expect_error("table --scenes cornell,cornell:size=2 --res 8x8" + out, "both named 'cornell'");
  expect_error("table --scenes cornell:sun=1/1/1 --res 8x8" + out, "scene 'cornell': unknown parameter 'sun'");
  const CommandResult r = run_shell("RAYCOH_MEMORY_AVAILABLE=1G $R table --res 8192x8192" + out);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--res 8192x8192: needs about"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("1.0 GiB are available"), std::string::npos) << r.output;
  expect_error("quality --res 16384x16384" + out, "GiB of memory");
  EXPECT_FALSE(fs::exists(dir / "o.csv.partial"));
  EXPECT_FALSE(fs::exists(dir / "o.csv"));
}

TEST(CliSafety, OneShotOutputsAreNotReplacedUnlessForced) {
  const auto dir = temp_dir("safety_once");
  const auto img = dir / "r.pfm";
  ASSERT_EQ(run_raycoh("render --res 16x16 --frames 1 --out " + img.string()).exit_code, 0);
  expect_error("render --res 16x16 --frames 1 --out " + img.string(), "already exists; pass --force");
  EXPECT_EQ(run_raycoh("render --res 16x16 --frames 1 --force --out " + img.string()).exit_code, 0);
  const auto rays = dir / "rays.csv";
  ASSERT_EQ(run_raycoh("rays --scene cornell --res 16x16 --out " + rays.string()).exit_code, 0);
  expect_error("rays --scene cornell --res 16x16 --out " + rays.string(), "already exists; pass --force");

  const std::string conv = "converge --scene cornell --res 16x16 --time 0.05s --ref-frames 2 --cache " +
                           (dir / "cache").string() + " --out " + (dir / "c.csv").string();
  ASSERT_EQ(run_raycoh(conv).exit_code, 0);
  const std::string curve = slurp(dir / "c.csv");
  CommandResult r = run_raycoh(conv);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("already hold the result of this same command"), std::string::npos) << r.output;
  EXPECT_EQ(slurp(dir / "c.csv"), curve);
  expect_error(conv + " --seed 2", "already holds a finished run");
  expect_no_leftovers(dir);
}

}  // namespace
}  // namespace raycoh::test
