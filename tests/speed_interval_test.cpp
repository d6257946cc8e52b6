// Intervals for measured speed (records/speed_interval.h): the order-statistic ranks and their coverage, the
// paired bootstrap ratio and the words a table may say of it.
#include "records/speed_interval.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>

#include "tests/cli_util.h"
#include "tests/test_util.h"

namespace raycoh::test {
namespace {

TEST(SpeedInterval, MedianRanksAndCoverage) {
  // n = 9: [x(2), x(8)] covers the median with 1 - 2 * 10/512 = 0.961; [x(3), x(7)] would be 0.820.
  const MedianInterval nine = median_interval({9, 1, 8, 2, 7, 3, 6, 4, 5});
  EXPECT_EQ(nine.median, 5);
  EXPECT_EQ(nine.lo, 2);
  EXPECT_EQ(nine.hi, 8);
  EXPECT_NEAR(nine.level, 1.0 - 20.0 / 512.0, 1e-12);
  // n = 5 cannot reach 95%: [min, max] at 1 - 2/32.
  const MedianInterval five = median_interval({5, 4, 3, 2, 1});
  EXPECT_EQ(five.lo, 1);
  EXPECT_EQ(five.hi, 5);
  EXPECT_NEAR(five.level, 0.9375, 1e-12);
  // n = 6: the median is the mean of the middle two; [min, max] at 1 - 2/64.
  const MedianInterval six = median_interval({1, 2, 3, 4, 5, 6});
  EXPECT_EQ(six.median, 3.5);
  EXPECT_NEAR(six.level, 1.0 - 2.0 / 64.0, 1e-12);
  // One sample: no interval.
  const MedianInterval one = median_interval({2.5});
  EXPECT_EQ(one.median, 2.5);
  EXPECT_EQ(one.level, 0);
}

TEST(SpeedInterval, OrderStatisticCoverageHoldsOnSimulatedTimes) {
  // 2000 runs of 9 skewed times whose true median is known: the interval holds it at least at its level (less a
  // sampling margin of 3 standard errors).
  std::mt19937_64 rng(7);
  std::exponential_distribution<double> tail(1.0);
  const double true_median = 1.0 + std::log(2.0);
  int hits = 0;
  const int runs = 2000;
  double level = 0;
  for (int r = 0; r < runs; ++r) {
    std::vector<double> t;
    for (int i = 0; i < 9; ++i) t.push_back(1.0 + tail(rng));
    const MedianInterval m = median_interval(t);
    hits += m.lo <= true_median && true_median <= m.hi;
    level = m.level;
  }
  const double se = std::sqrt(level * (1 - level) / runs);
  EXPECT_GE(double(hits) / runs, level - 3 * se);
}

std::vector<FrameTimes> frames(std::vector<std::vector<double>> times, double rays = 1000) {
  std::vector<FrameTimes> out;
  for (auto& t : times) out.push_back({std::move(t), rays});
  return out;
}

TEST(SpeedInterval, RatioPointEstimateIsTheMediansRatio) {
  const SpeedRatio r =
      speed_ratio(frames({{2.0, 2.1, 1.9}, {4.0, 4.2, 3.8}}), frames({{1.0, 1.1, 0.9}, {2.0, 2.1, 1.9}}));
  EXPECT_NEAR(r.ratio, 6.0 / 3.0, 1e-12);  // base medians 2 + 4, method 1 + 2
  EXPECT_TRUE(r.has_interval);
  EXPECT_LE(r.lo, r.ratio);
  EXPECT_GE(r.hi, r.ratio);
  EXPECT_EQ(speed_verdict(r), "faster");
  // Reproducible: a fixed bootstrap seed.
  const SpeedRatio again =
      speed_ratio(frames({{2.0, 2.1, 1.9}, {4.0, 4.2, 3.8}}), frames({{1.0, 1.1, 0.9}, {2.0, 2.1, 1.9}}));
  EXPECT_EQ(r.lo, again.lo);
  EXPECT_EQ(r.hi, again.hi);
}

TEST(SpeedInterval, OverlappingTimesAreIndistinguishableAndSeparatedOnesAreNot) {
  const auto base = frames({{1.00, 1.04, 0.97, 1.02, 0.99, 1.05, 0.96}});
  const SpeedRatio same = speed_ratio(base, frames({{1.01, 0.98, 1.03, 0.99, 1.02, 0.97, 1.04}}));
  EXPECT_LE(same.lo, 1.0);
  EXPECT_GE(same.hi, 1.0);
  EXPECT_EQ(speed_verdict(same), "indistinguishable");
  const SpeedRatio slower = speed_ratio(base, frames({{1.20, 1.22, 1.19, 1.25, 1.21, 1.23, 1.18}}));
  EXPECT_LT(slower.hi, 1.0);
  EXPECT_EQ(speed_verdict(slower), "slower");
}

TEST(SpeedInterval, OneRepeatHasNoInterval) {
  const SpeedRatio r = speed_ratio(frames({{2.0}}), frames({{1.0}}));
  EXPECT_NEAR(r.ratio, 2.0, 1e-12);
  EXPECT_FALSE(r.has_interval);
  EXPECT_EQ(speed_verdict(r), "no interval");
  EXPECT_EQ(ratio_text(r), "2.00x");
}

TEST(SpeedInterval, FramesMissingOnEitherSideAreSkipped) {
  const SpeedRatio r = speed_ratio(frames({{2.0, 2.0}, {}}), frames({{1.0, 1.0}, {5.0, 5.0}}));
  EXPECT_NEAR(r.ratio, 2.0, 1e-12);
  EXPECT_EQ(speed_ratio({}, {}).ratio, 0.0);
}

// The ranking's words: one method fastest where its interval over every other excludes 1, else the methods it
// cannot tell apart; the base (noopt) on top is 1.00x, with no interval against itself.
TEST(SpeedInterval, TheTopOfARankingIsNamedOnlyWhereTheIntervalsSeparateIt) {
  auto series = [](std::vector<double> times) {
    FrameSeries s;
    s[0] = {std::move(times), 1000};
    return s;
  };
  const FrameSeries noopt = series({1.00, 1.01, 0.99, 1.02, 0.98, 1.00, 1.01});
  const FrameSeries fast = series({0.50, 0.51, 0.49, 0.52, 0.48, 0.50, 0.51});
  const FrameSeries fast_too = series({0.505, 0.50, 0.495, 0.51, 0.49, 0.50, 0.52});
  const FrameSeries slow = series({2.0, 2.1, 1.9, 2.05, 1.95, 2.0, 2.02});
  EXPECT_EQ(
      top_of_ranking({{"noopt", &noopt}, {"fast", &fast}, {"slow", &slow}}, noopt).rfind("fast fastest, 2.00x [", 0),
      0u);
  const std::string tied = top_of_ranking({{"noopt", &noopt}, {"fast", &fast}, {"fast_too", &fast_too}}, noopt);
  EXPECT_EQ(tied.rfind("indistinguishable at the top: ", 0), 0u) << tied;
  EXPECT_NE(tied.find(", fast_too 2.00x ["), std::string::npos) << tied;
  EXPECT_EQ(top_of_ranking({{"noopt", &noopt}, {"slow", &slow}}, noopt), "noopt fastest, 1.00x");
  const FrameSeries once = series({1.0}), once_fast = series({0.5});
  EXPECT_EQ(top_of_ranking({{"noopt", &once}, {"fast", &once_fast}}, once),
            "fast highest, 2.00x (no repeated times in the rows: no interval, not called fastest)");
}

// scripts/speed_interval.py recomputes the report's intervals from the same rows, number for number (the GPU run
// summaries use it): every ratio cell and the top of the ranking, as `raycoh report` prints them.
TEST(SpeedInterval, ThePythonModuleGivesTheReportsIntervals) {
  const auto dir = temp_dir("speed_interval_py");
  const std::string csv = (dir / "t.csv").string();
  CommandResult r = run_raycoh(
      "table --scenes cornell --generators noopt,ours,contiguous --encoders none,origin "
      "--tracers cpu --res 48x32 --frames 3 --repeat 5 --out " +
      csv);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_raycoh("report " + csv + " --out " + (dir / "r.html").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<std::string> report = read_lines(dir / "r.md");
  const CommandResult py =
      run_shell("python3 " + std::string(RAYCOH_SOURCE_DIR) + "/scripts/speed_interval.py " + csv + " && python3 " +
                std::string(RAYCOH_SOURCE_DIR) + "/scripts/speed_interval.py " + csv + " --e2e");
  ASSERT_EQ(py.exit_code, 0) << py.output;
  int compared = 0;
  for (const std::string& line : report) {
    // "| ours | 1.11x [0.91, 1.26] / 1.09x [0.94, 1.20] |": trace / end to end, each printed by the module too.
    if (line.rfind("| ", 0) != 0 || line.find("x [") == std::string::npos) continue;
    const size_t name_end = line.find(" |", 2);
    const std::string method = line.substr(2, name_end - 2);
    const std::string cells = line.substr(name_end + 3, line.size() - name_end - 5);
    const size_t slash = cells.find(" / ");
    for (const std::string& cell : {cells.substr(0, slash), slash == std::string::npos ? "" : cells.substr(slash + 3)})
      if (!cell.empty()) {
        EXPECT_NE(py.output.find("  " + method + ": " + cell + "\n"), std::string::npos) << method << " " << cell;
        ++compared;
      }
  }
  EXPECT_EQ(compared, 1 + 2 * 5);  // primary (trace only) and five methods, noopt being the base
  const size_t top = py.output.find("  top: ");
  ASSERT_NE(top, std::string::npos);
  const std::string verdict = py.output.substr(top + 7, py.output.find('\n', top) - top - 7);
  bool found = false;
  for (const std::string& line : report) found = found || line.find("cornell: " + verdict) != std::string::npos;
  EXPECT_TRUE(found) << verdict;
}

}  // namespace
}  // namespace raycoh::test
