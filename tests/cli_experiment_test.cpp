// `table` and `sweep` from the command line: CSV rows, rows kept after an error, resume, printed tables.
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "generators/tangent_reuse.h"
#include "tests/cli_util.h"

namespace raycoh::test {
namespace {

TEST(CliExperiment, TableWritesItsCsvAndKeepsRowsWhenALaterSceneFails) {
  const auto dir = temp_dir("cli_table");
  const auto out = dir / "t.csv";
  CommandResult r =
      run_raycoh("table --scenes cornell --generators noopt --res 32x24 --frames 2 --repeat 1 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The heading names the tracer; its full parameters (bvh=bvh2) are printed once above the tables.
  EXPECT_NE(r.output.find("### cpu: secondary rays traced"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("- cpu: measured on this machine; cpu[bvh=bvh2]"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("| noopt | "), std::string::npos) << r.output;
  // 1 header + 2 frames x 2 tracers x (primary + noopt)
  EXPECT_EQ(count_lines(out), 1 + 2 * 2 * 2);
  EXPECT_FALSE(std::filesystem::exists(out.string() + ".partial"));

  const auto bad = dir / "bad.glb";
  write_file(bad, "glTF this is not a binary gltf");
  const auto out2 = dir / "t2.csv";
  r = run_raycoh("table --scenes cornell," + bad.string() +
                 " --generators noopt --res 32x24 --frames 1 --repeat 1 --out " + out2.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bad.glb"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out2));
  EXPECT_EQ(count_lines(out2.string() + ".partial"), 1 + 2 * 2);
  EXPECT_NE(r.output.find("(4 rows measured so far are kept in " + out2.string() + ".partial;"), std::string::npos)
      << r.output;

  // Nothing measured: no .partial is left behind and the error is the input's alone.
  const auto out3 = dir / "t3.csv";
  r = run_raycoh("table --scenes " + bad.string() +
                 ",cornell --generators noopt --res 32x24 --frames 1 --repeat 1 --out " + out3.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bad.glb"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("rows measured"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out3.string() + ".partial"));
}

// The default table is the comparison: noopt, ours, contiguous and noopt with every encoder, measured on the CPU
// and modeled on the GPU model (preset named once, labelled modeled), with the closing line naming the winners.
TEST(CliExperiment, TheDefaultTableShowsTheComparison) {
  const auto out = temp_dir("cli_default") / "t.csv";
  CommandResult r = run_raycoh("table --res 32x24 --frames 1 --repeat 1 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<std::string> methods = {"noopt",       "ours",        "contiguous", "noopt+origin",
                                            "noopt+reis",  "noopt+costa", "noopt+aila", "noopt+twopoint",
                                            "noopt+mlhcc", "noopt+window"};
  for (const std::string& m : methods) EXPECT_NE(r.output.find("| " + m + " |"), std::string::npos) << m;
  for (const char* s : {"| primary (coherent bound) |", "- simt[preset=rtx3060]: MODELED GPU figures",
                        "### simt[preset=rtx3060]: MODELED end to end", "### cpu: end to end",
                        "Fastest end to end (ratio to noopt [95% interval]):\n- cpu (measured), cornell: ",
                        "(no repeated times in the rows: no interval, not called fastest)",
                        "- simt[preset=rtx3060] (modeled), cornell: "})
    EXPECT_NE(r.output.find(s), std::string::npos) << s << "\n" << r.output;
  EXPECT_EQ(r.output.find("### simt[preset=rtx3060,kernel"), std::string::npos) << "the full parameters once only";
  // 2 scenes x 2 tracers (cpu, simt) x (primary + 10 methods), and the header
  EXPECT_EQ(count_lines(out), 1 + 2 * 2 * (1 + static_cast<int>(methods.size())));

  // Naming either list runs the product of both, the other one defaulting to noopt or none.
  const auto out2 = temp_dir("cli_default") / "t2.csv";
  r = run_raycoh("table --scenes cornell --encoders origin --tracers cpu --res 32x24 --frames 1 --repeat 1 --out " +
                 out2.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(count_lines(out2), 1 + 1 + 2);  // header, primary, noopt (the baseline), noopt+origin
  EXPECT_EQ(r.output.find("| ours |"), std::string::npos) << r.output;
}

// Timing tracers repeat each trace (7 on the CPU by default): every row carries its repeats, the median's
// order-statistic interval and its coverage; the console prints each ratio to noopt with its paired interval, and
// the closing line calls a method fastest only when the interval says so.
TEST(CliExperiment, MeasuredSpeedsCarryIntervals) {
  const auto out = temp_dir("cli_intervals") / "t.csv";
  CommandResult r = run_raycoh(
      "table --scenes cornell --generators noopt,contiguous --tracers cpu,simt --res 48x32 "
      "--frames 2 --out " +
      out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  int timed = 0;
  for (const auto& row : read_rows(out)) {
    if (row.at("tracer") == "simt") {  // a model: one run, no interval
      EXPECT_EQ(row.at("repeats"), "1");
      EXPECT_EQ(row.at("trace_samples_ms"), "");
      EXPECT_EQ(row.at("interval_level"), "");
      continue;
    }
    ++timed;
    EXPECT_EQ(row.at("repeats"), "7");
    const std::string samples = row.at("trace_samples_ms");
    EXPECT_EQ(std::count(samples.begin(), samples.end(), ';'), 6) << samples;
    EXPECT_NEAR(std::stod(row.at("interval_level")), 1.0 - 2.0 / 128.0, 1e-6);
    EXPECT_LE(std::stod(row.at("trace_ms_lo")), std::stod(row.at("trace_ms")) + 1e-4);
    EXPECT_GE(std::stod(row.at("trace_ms_hi")), std::stod(row.at("trace_ms")) - 1e-4);
    EXPECT_LE(std::stod(row.at("e2e_ms_lo")), std::stod(row.at("e2e_ms")) + 1e-4);
    // Generation is timed with every repeat too: each repeat's end to end is its generation plus its trace.
    const std::string gen = row.at("gen_samples_ms");
    if (row.at("pass") == "primary") {
      EXPECT_EQ(gen, "") << "a primary pass generates nothing";
      continue;
    }
    EXPECT_EQ(std::count(gen.begin(), gen.end(), ';'), 6) << gen;
    const auto numbers = [](const std::string& text) {
      std::vector<double> v;
      std::stringstream in(text);
      for (std::string w; std::getline(in, w, ';');) v.push_back(std::stod(w));
      return v;
    };
    const std::vector<double> g = numbers(gen), t = numbers(samples), e = numbers(row.at("e2e_samples_ms"));
    ASSERT_EQ(e.size(), 7u);
    for (size_t i = 0; i < e.size(); ++i) EXPECT_NEAR(e[i], g[i] + t[i], 2e-3) << i;
  }
  EXPECT_EQ(timed, 2 * 3);  // 2 frames x (primary, noopt, contiguous)
  for (const char* s : {"ratio to noopt [95% interval]); 48x32, 2 frame(s), seed 1, median of 7 traces", "| noopt | ",
                        "(1.00x), ", "Fastest end to end (ratio to noopt [95% interval]):"})
    EXPECT_NE(r.output.find(s), std::string::npos) << s << "\n" << r.output;
  // contiguous' cell has an interval; the verdict line either names one method fastest or says what it cannot tell.
  EXPECT_NE(r.output.find("| contiguous | "), std::string::npos);
  const size_t cell = r.output.find("| contiguous | ");
  EXPECT_NE(r.output.find("x [", cell), std::string::npos) << r.output;
  const bool named = r.output.find(" fastest, ") != std::string::npos;
  const bool tied = r.output.find("indistinguishable at the top: ") != std::string::npos;
  EXPECT_TRUE(named != tied) << r.output;
}

// Not on a terminal (a log): plain progress lines with the time left, throttled (RAYCOH_PROGRESS_SECONDS).
TEST(CliExperiment, ARunLogsProgressLinesWhenNotOnATerminal) {
  const auto out = temp_dir("cli_progress") / "p.csv";
  const CommandResult r = run_shell(
      "RAYCOH_PROGRESS_SECONDS=0 $R table --scenes cornell --generators noopt,ours --tracers cpu --res 32x24 "
      "--frames 2 --repeat 1 --out " +
      out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("progress:  75% cornell frame 2/2 ours (1/1, step 4/4)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(" s left\n"), std::string::npos) << r.output;
  // The default throttle: a short run prints no progress line.
  const CommandResult quiet = run_raycoh(
      "table --scenes cornell --generators noopt --tracers cpu --res 16x16 "
      "--frames 1 --repeat 1 --force --out " +
      out.string());
  EXPECT_EQ(quiet.output.find("progress:"), std::string::npos) << quiet.output;
}

TEST(CliExperiment, AnInterruptedTableResumesAndSkipsFinishedRows) {
  const auto dir = temp_dir("cli_resume");
  const auto out = dir / "r.csv";
  const std::string args =
      "table --scenes cornell --generators noopt --res 24x16 --frames 2 --repeat 1 --out " + out.string();
  ASSERT_EQ(run_raycoh(args).exit_code, 0);
  const auto complete = read_lines(out);
  ASSERT_EQ(complete.size(), 1u + 2 * 2 * 2);
  // An interrupted run: the header, three finished rows and a torn fourth one.
  std::filesystem::remove(out);
  write_file(out.string() + ".partial", complete[0] + "\n" + complete[1] + "\n" + complete[2] + "\n" + complete[3] +
                                            "\n" + complete[4].substr(0, 20));
  const CommandResult r = run_raycoh(args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("resuming: 3 rows"), std::string::npos) << r.output;
  const auto resumed = read_lines(out);
  ASSERT_EQ(resumed.size(), complete.size());
  for (int i = 0; i < 4; ++i) EXPECT_EQ(resumed[i], complete[i]);  // kept as measured, not measured again
  EXPECT_FALSE(std::filesystem::exists(out.string() + ".partial"));

  // A row of another code revision is refused, naming the field; --force starts afresh.
  const std::string stale = with_git_revision(complete[1], "0000000old");
  ASSERT_NE(stale.find(",0000000old,"), std::string::npos) << stale;
  std::filesystem::remove(out);
  write_file(out.string() + ".partial", complete[0] + "\n" + stale + "\n");
  const CommandResult again = run_raycoh(args);
  EXPECT_EQ(again.exit_code, 2) << again.output;
  EXPECT_NE(again.output.find("line 2 was measured with other parameters: its git_revision is '0000000old'"),
            std::string::npos)
      << again.output;
  const CommandResult forced = run_raycoh(args + " --force");
  ASSERT_EQ(forced.exit_code, 0) << forced.output;
  const auto fresh = read_lines(out);
  EXPECT_EQ(fresh.size(), complete.size());
  for (const auto& line : fresh) EXPECT_EQ(line.find("0000000old"), std::string::npos);
}

TEST(CliExperiment, SweepPrintsTheTileByGroupTable) {
  const auto out = temp_dir("cli_sweep") / "s.csv";
  const CommandResult r = run_raycoh(
      "sweep --scene cornell --tiles 4x4,8x8 --groups 4,32 --res 32x32 --frames 1 "
      "--repeat 1 --out " +
      out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("| (W,H) | K = 4 | K = 32 |"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("| (4,4) |"), std::string::npos);
  EXPECT_NE(r.output.find(" — |"), std::string::npos) << "K = 32 > 4x4 must be an empty cell\n" << r.output;
  // noopt + 3 valid cells, 1 tracer, 1 frame, plus primary and header
  EXPECT_EQ(count_lines(out), 1 + 1 + 4);
  expect_error("sweep --scene cornell --tiles 0x8", "--tiles");
  // A bad K is refused in one line naming the range of `ours`' parameter table (ours_params(), row k): the one rule.
  std::string k_range;
  for (const ParamSpec& row : ours_params())
    if (row.name == "k") k_range = "[" + std::to_string(int(row.lo)) + ", " + std::to_string(int(row.hi)) + "]";
  ASSERT_FALSE(k_range.empty());
  for (const char* bad : {"0", "70000", "x"}) {
    const CommandResult e = run_raycoh(std::string("sweep --scene cornell --groups ") + bad);
    EXPECT_EQ(e.exit_code, 2) << e.output;
    EXPECT_NE(e.output.find(std::string("--groups: '") + bad + "' is not valid; expected an integer in " + k_range),
              std::string::npos)
        << e.output;
    EXPECT_EQ(std::count(e.output.begin(), e.output.end(), '\n'), 1) << "one line\n" << e.output;
  }
  expect_error("sweep --scene cornell --generator noopt", "ours or contiguous");
}

TEST(CliExperiment, TableWithEncodersReportsTraceOnlyAndEndToEnd) {
  const auto out = temp_dir("cli_enc") / "e.csv";
  const CommandResult r = run_raycoh(
      "table --scenes cornell --generators noopt,ours --encoders none,origin,mlhcc "
      "--permute indirect --tracers cpu --res 32x24 --frames 1 --repeat 1 --out " +
      out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* s : {"| noopt+origin |", "| ours+mlhcc |", "end to end", "permute indirect"})
    EXPECT_NE(r.output.find(s), std::string::npos) << s << "\n" << r.output;
  const auto lines = read_lines(out);
  EXPECT_EQ(lines.size(), 1u + 1 + 6);  // header, primary, 2 generators x 3 encoders
  int indirect = 0;
  for (const auto& l : lines)
    indirect += l.find(",origin,\"bits=32") != std::string::npos && l.find(",indirect,") != std::string::npos;
  EXPECT_EQ(indirect, 2);
  expect_error("table --encoders zorder --res 8x8", "valid encoders: none, origin");
  expect_error("table --encoders origin --permute sideways --res 8x8", "physical");
}

TEST(CliExperiment, ADamagedLineOfAPartialFileIsSkippedNamingLineAndColumn) {
  const auto dir = temp_dir("cli_damaged");
  const auto out = dir / "d.csv";
  const std::string args =
      "table --scenes cornell --generators noopt --res 24x16 --frames 1 --repeat 1 --tracers cpu --out " + out.string();
  ASSERT_EQ(run_raycoh(args).exit_code, 0);
  auto lines = read_lines(out);
  ASSERT_EQ(lines.size(), 3u);
  // The scene_triangles field (2nd column) of a complete row no longer holds a number.
  std::string row = lines[1];
  const size_t first = row.find(','), second = row.find(',', first + 1);
  row = row.substr(0, first + 1) + "12x4" + row.substr(second);
  std::filesystem::remove(out);
  write_file(out.string() + ".partial", lines[0] + "\n" + row + "\n" + lines[2] + "\n");
  const CommandResult r = run_raycoh(args);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("d.csv.partial line 2 skipped: column scene_triangles: '12x4' is not an integer"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("resuming: 1 rows"), std::string::npos) << r.output;
  EXPECT_EQ(read_lines(out).size(), 3u);
  EXPECT_EQ(read_lines(out)[1], lines[2]);  // the good row, kept as measured
  EXPECT_EQ(read_lines(out.string() + ".rejected")[1], row);
}

TEST(CliExperiment, AWriteFailureIsReportedNotWritten) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const auto dir = temp_dir("cli_full");
  const auto out = dir / "f.csv";
  std::filesystem::create_symlink("/dev/full", out.string() + ".partial");
  // A ray dump never resumes, so the .partial (a full disk here) is only written, never read.
  const CommandResult r = run_raycoh("rays --scene cornell --res 16x16 --out " + out.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("write failed"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("wrote"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(CliExperiment, ValidatePutsTheModelBesideThePaper) {
  const auto dir = temp_dir("cli_validate");
  const auto out = dir / "v.csv";
  const CommandResult r = run_raycoh("validate --scene voxels:size=16 --res 48x32 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("MODELED, not measured"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("| AilaCompact | 208.9 | 1.35 |"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("| (32,8) |"), std::string::npos) << r.output;
  // 7 rows of Table 1, 16 cells of Table 3, the primary-ray bound.
  const auto lines = read_lines(out);
  ASSERT_EQ(lines.size(), 1u + 7 + 16 + 1);
  EXPECT_EQ(lines[0].rfind("table,row,paper_scene,paper_row,tile,k,paper_mray_s,paper_ratio,kind,modeled_mray_s,"
                           "modeled_ratio,measured_mray_s,",
                           0),
            0u)
      << lines[0];
  EXPECT_EQ(lines[1].rfind("table1,noopt,Sibenik,NoOpt,,0,154.7,1,modeled,", 0), 0u) << lines[1];
  EXPECT_TRUE(std::filesystem::exists(out.string() + ".md"));
  EXPECT_EQ(count_lines(out.string() + ".rows.csv"), 1 + 22 + 1);  // 22 methods and the primary pass, one frame
  expect_error("validate --scene /nonexistent/sibenik --out " + (dir / "w.csv").string(), "Sibenik");
  expect_error("validate --scene voxels:size=16 --res 48x32 --preset gtx480 --out " + (dir / "w.csv").string(),
               "rtx3060, h100");
  expect_error("validate --scene voxels:size=16 --stand-ins " + dir.string() + " --out " + (dir / "w.csv").string(),
               "no country_kitchen in it (the stand-in for the paper's Breakfast)");
}

// A measuring tracer instead of the model: Table 1 on the paper's five scene types (the stand-ins from the shared
// scenes), Table 3 on Sibenik, each measured ratio with its paired interval and whether the paper's ratio lies in
// it. (The CPU tracer here, so that it runs anywhere; scripts/gpu-check --validate runs it on cuda.)
TEST(CliExperiment, ValidateMeasuresTheTablesWithIntervals) {
  const auto scenes = shared_scenes_dir();
  if (scenes.empty() || !std::filesystem::exists(scenes / "lost_empire")) GTEST_SKIP() << "no shared scenes";
  const auto dir = temp_dir("cli_validate_measured");
  const auto out = dir / "v.csv";
  const CommandResult r = run_raycoh("validate --tracer cpu --scene " + (scenes / "sibenik").string() +
                                     " --stand-ins " + scenes.string() + " --res 24x16 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* s : {"MEASURED on cpu", "### Table 1, Vokselia column (lost_empire)",
                        "### Table 1, Breakfast column (country_kitchen)", "the paper's ratio inside our 95% interval"})
    EXPECT_NE(r.output.find(s), std::string::npos) << s << "\n" << r.output;
  const auto rows = read_rows(out);
  ASSERT_EQ(rows.size(), 5u * 7 + 16 + 1);  // Table 1 on five columns, Table 3, the primary bound
  for (const auto& row : rows) {
    EXPECT_EQ(row.at("kind"), "measured");
    EXPECT_EQ(row.at("modeled_ratio"), "");
    if (row.at("row") == "noopt") {  // the base: no interval
      EXPECT_EQ(row.at("ratio_lo"), "");
      continue;
    }
    EXPECT_LE(std::stod(row.at("ratio_lo")), std::stod(row.at("measured_ratio")) + 1e-9) << row.at("row");
    EXPECT_GE(std::stod(row.at("ratio_hi")), std::stod(row.at("measured_ratio")) - 1e-9) << row.at("row");
    if (row.at("table") != "bound") {
      EXPECT_TRUE(row.at("paper_in_interval") == "yes" || row.at("paper_in_interval") == "no");
    }
  }
  EXPECT_EQ(count_lines(out.string() + ".table1-rows.csv"), 1 + 4 * (7 + 1));  // four stand-ins, 7 methods + primary
}

}  // namespace
}  // namespace raycoh::test
