// `raycoh tune`'s speed answer: the speed call on known intervals, the speedup's interval columns of a measured
// tune, a model's tune without one and its small-batch warning, and --confirm on fresh seeds.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "harness/tune/tune_select.h"
#include "tests/cli_util.h"

namespace raycoh::test {
namespace {

TuneCandidate passing(int k, double speed, SpeedRatio to_paper) {
  TuneCandidate c;
  c.setting.k = k;
  c.speed = c.trace_speed = speed;
  c.error_measured = true;
  c.ds8 = {1, 1, 1, 4};
  c.bias_verdict = "consistent";
  c.to_paper = to_paper;
  return c;
}

SpeedRatio ratio(double r, double lo, double hi, bool interval = true) { return {r, lo, hi, interval}; }

TEST(TuneSpeedCall, ASettingIsRecommendedOverThePapersOnlyWhenMeasuredFaster) {
  const TuneBudget budget = parse_tune_budget("ds8=2,bias=none");
  auto settle = [&](SpeedRatio to_paper) {
    const std::vector<TuneCandidate> cs{passing(8, 100, ratio(1, 1, 1)), passing(16, 110, to_paper)};
    TuneChoice ch = choose(cs, budget);
    settle_speed(ch, cs, 0);
    EXPECT_EQ(ch.fastest_passing, 1);
    return ch;
  };
  const TuneChoice faster = settle(ratio(1.1, 1.04, 1.16));
  EXPECT_EQ(faster.recommended, 1);
  EXPECT_EQ(faster.speed_call, "faster");
  const TuneChoice tied = settle(ratio(1.1, 0.97, 1.25));
  EXPECT_EQ(tied.recommended, 0);  // indistinguishable at 95%: the paper's default
  EXPECT_EQ(tied.speed_call, "indistinguishable");
  const TuneChoice modeled = settle(ratio(1.1, 1.1, 1.1, false));
  EXPECT_EQ(modeled.recommended, 1);  // one modeled run: the point figure stands
  EXPECT_EQ(modeled.speed_call, "no interval");
  // The paper's default missing the budget keeps the fastest passing setting, whatever its interval.
  std::vector<TuneCandidate> cs{passing(8, 100, ratio(1, 1, 1)), passing(16, 110, ratio(1.1, 0.97, 1.25))};
  cs[0].ds8 = {3, 3, 3, 4};
  TuneChoice ch = choose(cs, budget);
  settle_speed(ch, cs, 0);
  EXPECT_EQ(ch.recommended, 1);
}

const std::string kSmall =
    "tune --scene cornell --res 24x16 --space \"tile=8x8 k=8,16 order=tile hybrid=paper frame=duff\" "
    "--budget ds8=100,bias=any --frames 2 --seeds 2 --ref-frames 8 --speed-frames 2 --search grid";

double num(const std::string& s) { return s.empty() ? std::nan("") : std::stod(s); }

// A measured tune (cpu, 3 repeats): every row holds its speedup's interval, lo <= speedup <= hi, and a verdict
// against the paper's default; the cpu is no GPU, so no waves.
TEST(CliTuneSpeed, AMeasuredTuneStatesTheSpeedupsInterval) {
  const auto dir = temp_dir("cli_tune_speed");
  const CommandResult r = run_raycoh(kSmall + " --tracer cpu --repeat 3 --cache " + (dir / "cache").string() +
                                     " --out " + (dir / "t.csv").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto rows = read_rows(dir / "t.csv");
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& row : rows) {
    const double up = num(row.at("speedup")), lo = num(row.at("speedup_lo")), hi = num(row.at("speedup_hi"));
    EXPECT_LE(lo, up) << row.at("setting");
    EXPECT_GE(hi, up) << row.at("setting");
    EXPECT_EQ(row.at("speed_repeats"), "3");
    EXPECT_EQ(row.at("waves"), "");
    EXPECT_NE(row.at("vs_paper_verdict"), "no interval");
  }
  EXPECT_NE(r.output.find("3 repeats each; speed ratios with their 95% paired interval"), std::string::npos)
      << r.output;
  EXPECT_TRUE(r.output.find("\nRecommended:") != std::string::npos ||
              r.output.find("\nNo setting meets the budget") != std::string::npos)
      << r.output;
}

// A model's tune: one deterministic run, no interval (said so), and at 24x16 the batch is far from filling the
// modelled RTX 3060 (28 SMs): the warning.
TEST(CliTuneSpeed, AModelsTuneSaysNoIntervalAndWarnsOfASmallBatch) {
  const auto dir = temp_dir("cli_tune_simt");
  const CommandResult r =
      run_raycoh(kSmall + " --cache " + (dir / "cache").string() + " --out " + (dir / "t.csv").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("one MODELED run each: no interval"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("too small to fill the GPU: speed ranks may not carry to a full frame"), std::string::npos)
      << r.output;
  for (const auto& row : read_rows(dir / "t.csv")) {
    EXPECT_EQ(row.at("speedup_lo"), "");
    EXPECT_EQ(row.at("vs_paper_verdict"), row.at("paper_default") == "1" ? "" : "no interval");
    EXPECT_GT(num(row.at("waves")), 0);
    EXPECT_LT(num(row.at("waves")), 2);
  }
}

// --confirm 2: two fresh seeds (after the search's seed 1 and its renders' 1..2: 3 and 4), a line each, the closing
// line and <stem>-confirm.csv with a row per seed and the pooled one.
TEST(CliTuneSpeed, ConfirmRemeasuresTheCallOnFreshSeeds) {
  const auto dir = temp_dir("cli_tune_confirm");
  const CommandResult r = run_raycoh(kSmall + " --tracer cpu --repeat 3 --confirm 2 --cache " +
                                     (dir / "cache").string() + " --out " + (dir / "t.csv").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("at 2 fresh seed(s) from 3"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("  seed 3: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("  seed 4: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("of 2 fresh seeds"), std::string::npos) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "t-confirm-seed3-speed.csv"));
  EXPECT_FALSE(std::filesystem::exists(dir / "t-confirm-seed1-speed.csv"));
  const auto rows = read_rows(dir / "t-confirm.csv");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].at("seeds"), "3");
  EXPECT_EQ(rows[2].at("kind"), "pooled");
  EXPECT_EQ(rows[2].at("seeds"), "3;4");
  for (const auto& row : rows) {
    const std::string held = row.at("held");
    EXPECT_TRUE(held == "held" || held == "not held" || held == "indistinguishable") << held;
  }
  // The report shows the confirmation beside the tune itself.
  const CommandResult rep = run_raycoh("report " + (dir / "t.csv").string() + " " + (dir / "t-confirm.csv").string() +
                                       " --out " + (dir / "r.html").string());
  ASSERT_EQ(rep.exit_code, 0) << rep.output;
  std::string md;
  for (const std::string& line : read_lines(dir / "r.md")) md += line + "\n";
  EXPECT_NE(md.find("## Tune's speed call confirmed on fresh seeds"), std::string::npos) << md;
  EXPECT_NE(md.find("| 3;4 (pooled) |"), std::string::npos) << md;
}

TEST(CliTuneSpeed, ConfirmChecksItsRange) {
  expect_error("tune --scene cornell --budget ds8=2 --confirm 0", "--confirm 0: must be in [1, 64]");
  expect_error("tune --scene cornell --budget ds8=2 --confirm 65", "--confirm 65: must be in [1, 64]");
}

}  // namespace
}  // namespace raycoh::test
