// `--shard I/N` and `raycoh merge` end to end: shards together are the single process's rows, a resumed shard
// redoes and doubles nothing, and merge refuses what does not belong together or is incomplete.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>

#include "records/csv.h"
#include "records/merge.h"
#include "shading/image.h"
#include "shading/reference.h"
#include "tests/cli_util.h"

namespace raycoh::test {
namespace {

namespace fs = std::filesystem;

// Columns whose values differ between runs of the same work: measured times, and where and how a run was started.
const std::set<std::string> kExperimentTimes = {"gen_ms",     "trace_ms", "trace_ms_min", "mray_s",
                                                "key_ms",     "sort_ms",  "permute_ms",   "e2e_ms",
                                                "e2e_mray_s", "host",     "started_utc",  "command_line"};

// quality and converge: measured times (and what is read off them), and where and how a run was started.
const std::set<std::string> kRenderTimes = {"render_s",
                                            "trace_s",
                                            "gen_ms",
                                            "mray_s",
                                            "wall_s",
                                            "gen_s",
                                            "frame_wall_ms",
                                            "frame_trace_ms",
                                            "horizon_s",
                                            "error",
                                            "baseline_error",
                                            "equal_time_error_ratio",
                                            "time_s",
                                            "baseline_time_s",
                                            "equal_error_speedup",
                                            "error_corr",
                                            "baseline_error_corr",
                                            "equal_time_error_ratio_corr",
                                            "ref_noise_share",
                                            "ref_noise_residual_share",
                                            "host",
                                            "started_utc",
                                            "command_line"};

// The file's rows with the non-deterministic columns blanked, sorted (header first).
std::vector<std::string> deterministic_rows(const fs::path& p,
                                            const std::set<std::string>& not_deterministic = kExperimentTimes) {
  std::vector<std::string> lines = read_lines(p), header, out;
  if (lines.empty()) return out;
  csv_parse_line(lines[0], header);
  out.push_back(lines[0]);
  for (size_t i = 1; i < lines.size(); ++i) {
    std::vector<std::string> f;
    csv_parse_line(lines[i], f);
    std::string row;
    for (size_t c = 0; c < f.size() && c < header.size(); ++c)
      row += (not_deterministic.count(header[c]) ? std::string("-") : f[c]) + ",";
    out.push_back(row);
  }
  std::sort(out.begin() + 1, out.end());
  return out;
}

const std::string kRun =
    "table --scenes cornell,voxels:size=8 --generators noopt,ours --encoders none,origin --tracers cpu,simt "
    "--res 32x24 --frames 2 --repeat 1";

TEST(CliShard, ThreeShardsMergeToTheSingleProcessRows) {
  const auto dir = temp_dir("cli_shard");
  const auto whole = dir / "whole.csv", merged = dir / "merged.csv";
  CommandResult r = run_raycoh(kRun + " --out " + whole.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::string shards;
  size_t shard_rows = 0;
  for (int i = 0; i < 3; ++i) {
    const auto out = dir / ("shard" + std::to_string(i) + ".csv");
    r = run_raycoh(kRun + " --shard " + std::to_string(i) + "/3 --out " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("raycoh merge"), std::string::npos) << r.output;
    shard_rows += read_lines(out).size() - 1;
    EXPECT_LT(read_lines(out).size() - 1, read_lines(whole).size() - 1);  // each shard does a part
    shards += " " + out.string();
  }
  EXPECT_EQ(shard_rows, read_lines(whole).size() - 1);
  r = run_raycoh("merge --out " + merged.string() + shards);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("of 3 shard(s)"), std::string::npos) << r.output;
  EXPECT_EQ(deterministic_rows(merged), deterministic_rows(whole));
  // Merging again refuses the existing output; --force replaces it.
  expect_error("merge --out " + merged.string() + shards, merged.string());
  EXPECT_EQ(run_raycoh("merge --force --out " + merged.string() + shards).exit_code, 0);
}

TEST(CliShard, AResumedShardRedoesAndDoublesNothing) {
  const auto dir = temp_dir("cli_shard_resume");
  const std::string run = "table --scenes cornell --generators noopt,ours --res 24x16 --frames 3 --repeat 1";
  std::string shards;
  std::vector<std::string> first;
  for (int i = 0; i < 2; ++i) {
    const auto out = dir / ("s" + std::to_string(i) + ".csv");
    ASSERT_EQ(run_raycoh(run + " --shard " + std::to_string(i) + "/2 --out " + out.string()).exit_code, 0);
    shards += " " + out.string();
    if (i == 0) first = read_lines(out);
  }
  ASSERT_GE(first.size(), 4u);
  // Shard 0 killed after two rows: its .partial holds them; the same command measures only the rest.
  const auto s0 = dir / "s0.csv";
  fs::remove(s0);
  write_file(s0.string() + ".partial", first[0] + "\n" + first[1] + "\n" + first[2] + "\n");
  const CommandResult r = run_raycoh(run + " --shard 0/2 --out " + s0.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("resuming: 2 rows"), std::string::npos) << r.output;
  const auto again = read_lines(s0);
  ASSERT_EQ(again.size(), first.size());
  EXPECT_EQ(again[1], first[1]);  // kept as measured
  EXPECT_EQ(again[2], first[2]);
  const auto merged = dir / "m.csv";
  const CommandResult m = run_raycoh("merge --out " + merged.string() + shards);
  ASSERT_EQ(m.exit_code, 0) << m.output;
  const auto whole = dir / "whole.csv";
  ASSERT_EQ(run_raycoh(run + " --out " + whole.string()).exit_code, 0);
  EXPECT_EQ(deterministic_rows(merged), deterministic_rows(whole));
}

TEST(CliShard, MergeRefusesWhatDoesNotBelongTogetherNamingFilesAndField) {
  const auto dir = temp_dir("cli_merge_refuse");
  const std::string run = "table --scenes cornell --generators noopt --res 24x16 --frames 2 --repeat 1 --tracers cpu";
  const auto a = dir / "a.csv", b = dir / "b.csv", out = dir / "out.csv";
  ASSERT_EQ(run_raycoh(run + " --shard 0/2 --out " + a.string()).exit_code, 0);
  ASSERT_EQ(run_raycoh(run + " --shard 1/2 --out " + b.string()).exit_code, 0);

  // A missing shard is named; nothing is written.
  expect_error("merge --out " + out.string() + " " + a.string(), "shard(s) 1/2 missing");
  EXPECT_FALSE(fs::exists(out));
  // A shard that did not finish: its file is named with the rows its .partial holds.
  const auto c = dir / "c.csv";
  write_file(c.string() + ".partial", read_lines(a)[0] + "\n" + read_lines(a)[1] + "\n");
  expect_error("merge --out " + out.string() + " " + a.string() + " " + c.string(),
               c.string() + " (unfinished: " + c.string() + ".partial holds 1 row(s)");
  // A row gone from a shard's file: the row and the shard that owes it are named.
  const auto a_lines = read_lines(a);
  ASSERT_GE(a_lines.size(), 3u);
  std::string cut;
  for (size_t i = 0; i + 1 < a_lines.size(); ++i) cut += a_lines[i] + "\n";
  const auto short_a = dir / "short.csv";
  write_file(short_a, cut);
  expect_error("merge --out " + out.string() + " " + short_a.string() + " " + b.string(),
               "1 row(s) missing (shard 0/2: 1)");
  // The same rows twice (a copy of a shard's file) are duplicates.
  const auto copy = dir / "copy.csv";
  fs::copy_file(a, copy);
  expect_error("merge --out " + out.string() + " " + a.string() + " " + b.string() + " " + copy.string(),
               "duplicate row(s)");
  // Another code revision: both files and the field are named.
  std::vector<std::string> lines = read_lines(b);
  std::string edited = lines[0] + "\n";
  for (size_t i = 1; i < lines.size(); ++i) edited += with_git_revision(lines[i], "0000000old") + "\n";
  const auto other = dir / "other.csv";
  write_file(other, edited);
  const CommandResult r = run_raycoh("merge --out " + out.string() + " " + a.string() + " " + other.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  for (const std::string& s : {a.string(), other.string(), std::string("git_revision"), std::string("0000000old")})
    EXPECT_NE(r.output.find(s), std::string::npos) << s << "\n" << r.output;
  // Other parameters: the field named (a different resolution), then the rest of the command line.
  const auto res = dir / "res.csv", frames = dir / "frames.csv";
  ASSERT_EQ(run_raycoh("table --scenes cornell --generators noopt --res 16x16 --frames 2 --repeat 1 --tracers cpu "
                       "--shard 1/2 --out " +
                       res.string())
                .exit_code,
            0);
  expect_error("merge --out " + out.string() + " " + a.string() + " " + res.string(), "disagree on width");
  ASSERT_EQ(run_raycoh("table --scenes cornell --generators noopt --res 24x16 --frames 2 --repeat 2 --tracers cpu "
                       "--shard 1/2 --out " +
                       frames.string())
                .exit_code,
            0);
  expect_error("merge --out " + out.string() + " " + a.string() + " " + frames.string(), "disagree on the parameters");
  // Unfinished files and a shard count that differs are refused too.
  write_file(dir / "x.csv.partial", lines[0] + "\n");
  expect_error("merge --out " + out.string() + " " + a.string() + " " + (dir / "x.csv.partial").string(), "unfinished");
  EXPECT_FALSE(fs::exists(out));
  ASSERT_EQ(run_raycoh("merge --out " + out.string() + " " + a.string() + " " + b.string()).exit_code, 0);
}

// The named columns of every row, in file order.
std::vector<std::string> columns_of(const fs::path& p, const std::vector<std::string>& names) {
  std::vector<std::string> lines = read_lines(p), header, out;
  if (lines.empty()) return out;
  csv_parse_line(lines[0], header);
  for (size_t i = 1; i < lines.size(); ++i) {
    std::vector<std::string> f;
    csv_parse_line(lines[i], f);
    std::string row;
    for (const std::string& n : names) row += f[std::find(header.begin(), header.end(), n) - header.begin()] + " ";
    out.push_back(row);
  }
  return out;
}

// quality --shard: three shards started at once race for the two scenes' references; the cache's entry lock lets
// one shard render each while the others wait and read it. The merged file is the single process's rows.
const std::string kQuality =
    "quality --scenes cornell,voxels:size=8 --generators noopt,ours,contiguous --res 32x24 --ref-frames 8 "
    "--bias-renders 2";

TEST(CliShard, QualityShardsRacingForTheReferencesMergeToTheSingleProcessRows) {
  const auto dir = temp_dir("cli_quality_shard");
  const std::string d = dir.string();
  const CommandResult shards =
      run_shell("cd " + d + " && for i in 0 1 2; do \"$R\" " + kQuality + " --frames 2 --cache " + d +
                "/cache --images images --shard $i/3 --out q$i.csv > log$i 2>&1 & pids=\"$pids $!\"; done; "
                "for p in $pids; do wait $p || exit 1; done; cat log0 log1 log2");
  ASSERT_EQ(shards.exit_code, 0) << shards.output;
  size_t rendered = 0;
  for (size_t at = 0; (at = shards.output.find("reference: rendered", at)) != std::string::npos; ++at) ++rendered;
  EXPECT_EQ(rendered, 2u) << shards.output;  // once per scene, whoever rendered it
  EXPECT_NE(shards.output.find("raycoh merge"), std::string::npos) << shards.output;
  // Every image once in the shared --images folder: 2 scenes x (3 generators x (render, bias map PNG and EXR) + the
  // reference).
  EXPECT_EQ(std::distance(fs::directory_iterator(dir / "images"), fs::directory_iterator{}), 20);
  const CommandResult whole = run_raycoh(kQuality + " --frames 2 --cache " + d + "/cache --out " + d + "/whole.csv");
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  const CommandResult m = run_raycoh("merge --out " + d + "/m.csv " + d + "/q0.csv " + d + "/q1.csv " + d + "/q2.csv");
  ASSERT_EQ(m.exit_code, 0) << m.output;
  ASSERT_EQ(read_lines(dir / "m.csv").size(), 7u);
  EXPECT_EQ(deterministic_rows(dir / "m.csv", kRenderTimes), deterministic_rows(dir / "whole.csv", kRenderTimes));
  // In one process's order (scene, then generator).
  EXPECT_EQ(columns_of(dir / "m.csv", {"scene_spec", "method"}),
            columns_of(dir / "whole.csv", {"scene_spec", "method"}));

  // Refused, nothing written: a shard of other parameters (both files and the field named); a missing shard and
  // a duplicate, named together.
  const std::string out = d + "/bad.csv";
  ASSERT_EQ(run_raycoh(kQuality + " --frames 3 --cache " + d + "/cache --shard 2/3 --out " + d + "/f3.csv").exit_code,
            0);
  const CommandResult r = run_raycoh("merge --out " + out + " " + d + "/q0.csv " + d + "/q1.csv " + d + "/f3.csv");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  for (const std::string& part : {d + "/q0.csv", d + "/f3.csv", std::string("disagree on frames: '2' vs '3'")})
    EXPECT_NE(r.output.find(part), std::string::npos) << part << "\n" << r.output;
  fs::copy_file(dir / "q1.csv", dir / "copy.csv");
  const CommandResult twice =
      run_raycoh("merge --out " + out + " " + d + "/q0.csv " + d + "/q1.csv " + d + "/copy.csv");
  EXPECT_EQ(twice.exit_code, 2) << twice.output;
  for (const std::string& part : {std::string("shard(s) 2/3 missing"), std::string("duplicate quality row(s)")})
    EXPECT_NE(twice.output.find(part), std::string::npos) << part << "\n" << twice.output;
  EXPECT_FALSE(fs::exists(out));
}

// converge --shard: each shard renders the baseline beside its generators (its rows written by the baseline's
// shard only); 3 shards of 2 generators (one owns none) merge into the single process's curves and summary rows.
TEST(CliShard, ConvergeShardsMergeToTheSingleProcessCurves) {
  const auto dir = temp_dir("cli_converge_shard");
  const std::string d = dir.string();
  const std::string run =
      "converge --scene cornell --generators noopt,contiguous --res 32x24 --ref-frames 8 --time 1000s --max-frames 3 "
      "--cache " +
      d + "/cache";
  ASSERT_EQ(run_raycoh(run + " --out " + d + "/whole.csv").exit_code, 0);
  std::string inputs;
  for (int i = 0; i < 3; ++i) {
    const std::string out = d + "/c" + std::to_string(i) + ".csv";
    const CommandResult r = run_raycoh(run + " --shard " + std::to_string(i) + "/3 --out " + out);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    inputs += " " + out;
  }
  // A per-frame file without its summary is named.
  fs::rename(dir / "c2-summary.csv", dir / "moved.csv");
  expect_error("merge --out " + d + "/m.csv" + inputs, d + "/c2-summary.csv (no such file)");
  fs::rename(dir / "moved.csv", dir / "c2-summary.csv");
  const CommandResult m = run_raycoh("merge --out " + d + "/m.csv" + inputs);
  ASSERT_EQ(m.exit_code, 0) << m.output;
  EXPECT_EQ(read_lines(dir / "m.csv").size(), 1u + 2 * 3);
  EXPECT_EQ(deterministic_rows(dir / "m.csv", kRenderTimes), deterministic_rows(dir / "whole.csv", kRenderTimes));
  EXPECT_EQ(read_lines(dir / "m-summary.csv").size(), 1u + 3);  // clocks wall, trace, modeled_gpu
  EXPECT_EQ(deterministic_rows(dir / "m-summary.csv", kRenderTimes),
            deterministic_rows(dir / "whole-summary.csv", kRenderTimes));
  // Round by round, as one process writes them: frame, then generator.
  EXPECT_EQ(columns_of(dir / "m.csv", {"frame", "method"}), columns_of(dir / "whole.csv", {"frame", "method"}));
  EXPECT_EQ(columns_of(dir / "m-summary.csv", {"method", "clock"}),
            columns_of(dir / "whole-summary.csv", {"method", "clock"}));
}

TEST(CliShard, CommandWordsUndoTheProvenanceQuoting) {
  EXPECT_EQ(command_words("build/raycoh table --scenes 'a b' --out x.csv"),
            (std::vector<std::string>{"table", "--scenes", "a b", "--out", "x.csv"}));
  EXPECT_EQ(command_words("r --x 'it'\\''s'"), (std::vector<std::string>{"--x", "it's"}));
}

// `raycoh reference --shard I/N` parts, joined by `reference-combine`, are the cache entry `raycoh reference` (and
// so quality's --ref-frames) writes, bit for bit; a resubmitted part is not rendered again; misaligned shards
// are refused.
TEST(CliShard, ReferenceFrameShardsCombineToTheSingleProcessEntry) {
  const auto dir = temp_dir("cli_ref_shard");
  const std::string ref = "reference --scene cornell --res 8x6 --seed 3 --frames 512";
  CommandResult r = run_raycoh(ref + " --cache " + (dir / "single").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::string parts;
  for (int i = 0; i < 8; ++i) {
    const auto part = dir / ("part" + std::to_string(i));
    r = run_raycoh(ref + " --shard " + std::to_string(i) + "/8 --out " + part.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    parts += " " + part.string();
  }
  r = run_raycoh(ref + " --shard 5/8 --out " + (dir / "part5").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("already rendered"), std::string::npos) << r.output;
  r = run_raycoh("reference-combine --cache " + (dir / "combined").string() + parts);
  ASSERT_EQ(r.exit_code, 0) << r.output;

  std::vector<fs::path> single, combined;
  for (const auto& e : fs::directory_iterator(dir / "single"))
    if (e.path().extension() != ".json" && e.path().stem().string().find("-half1") == std::string::npos)
      single.push_back(e.path());
  ASSERT_EQ(single.size(), 1u);
  // The first-half image (the reference-noise estimate's) is written both ways, the same pixels.
  const fs::path half = half_reference_path(single[0].string());
  ASSERT_TRUE(fs::exists(half));
  ASSERT_TRUE(fs::exists(dir / "combined" / half.filename())) << r.output;
  const Image ha = read_image(half.string()), hb = read_image((dir / "combined" / half.filename()).string());
  ASSERT_EQ(ha.rgb.size(), hb.rgb.size());
  EXPECT_EQ(std::memcmp(ha.rgb.data(), hb.rgb.data(), ha.rgb.size() * sizeof(float)), 0);
  const fs::path twin = dir / "combined" / single[0].filename();
  ASSERT_TRUE(fs::exists(twin)) << r.output;
  // The same pixels, bit for bit (an EXR header also holds its write time, so not the same bytes).
  const Image a = read_image(single[0].string()), b = read_image(twin.string());
  ASSERT_EQ(a.rgb.size(), 3u * 8 * 6);
  ASSERT_EQ(b.rgb.size(), a.rgb.size());
  EXPECT_EQ(std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)), 0);
  r = run_raycoh(ref + " --cache " + (dir / "combined").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("(cache)"), std::string::npos) << r.output;

  expect_error(ref + " --shard 0/3 --out " + (dir / "bad").string(), "valid shard counts: 1, 2, 4, 8");
  expect_error(ref + " --shard 0/8", "--shard I/N needs --out PART");
  // --out alone (or --shard 0/1): one part holding every block, which combines to the same entry.
  r = run_raycoh(ref + " --shard 0/1 --out " + (dir / "one.part").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_raycoh("reference-combine --cache " + (dir / "one").string() + " " + (dir / "one.part").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Image one = read_image((dir / "one" / single[0].filename()).string());
  ASSERT_EQ(one.rgb.size(), a.rgb.size());
  EXPECT_EQ(std::memcmp(one.rgb.data(), a.rgb.data(), a.rgb.size() * sizeof(float)), 0);
  expect_error("reference-combine --cache " + (dir / "c2").string() + " " + (dir / "part0").string(),
               "7 of 8 reference shard(s) missing");
}

}  // namespace
}  // namespace raycoh::test
