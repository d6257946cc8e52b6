// `raycoh report`: the page and the summary render from the committed results; bad input is a one-line error.
// The browser check (RAYCOH_BROWSER_TEST=1, Debian's chromium) loads the page headless, finds no console message
// and saves a screenshot (RAYCOH_BROWSER_SCREENSHOT, default <temp>/report.png).
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "shading/image.h"
#include "tests/cli_util.h"

namespace raycoh::test {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Every CSV committed under results/ (top level): table, sweep, converge curves and summaries, quality.
std::string committed_results() {
  std::vector<std::string> csvs;
  for (const auto& e : fs::directory_iterator(fs::path(RAYCOH_SOURCE_DIR) / "results"))
    if (e.path().extension() == ".csv") csvs.push_back(e.path().string());
  std::sort(csvs.begin(), csvs.end());
  std::string args;
  for (const std::string& c : csvs) args += " " + c;
  return args;
}

fs::path render_committed(const std::string& name) {
  const fs::path dir = temp_dir(name);
  const CommandResult r = run_raycoh("report" + committed_results() + " " + fs::path(RAYCOH_SOURCE_DIR).string() +
                                     "/results/model/validate/tile.csv --out " + (dir / "report.html").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("Wrote " + (dir / "report.html").string() + " and " + (dir / "report.md").string()),
            std::string::npos)
      << r.output;
  return dir;
}

TEST(CliReport, RendersThePageAndSummaryFromTheCommittedResults) {
  const fs::path dir = render_committed("cli_report");
  const std::string html = slurp(dir / "report.html"), md = slurp(dir / "report.md");
  for (const char* s : {"<!DOCTYPE html>",
                        "<h2>Table 1 layout:",
                        "table_sibenik_kitchen.csv",
                        "<h2>Table 3 layout:",
                        "sweep_sibenik.csv",
                        "Error against time",
                        "rel_mse against CPU wall-clock s",
                        "data:image/png;base64,",
                        "colour = generator:",
                        "shade = encoder",
                        "simt[preset=rtx3060]: trace only, modeled",
                        "MODELED GPU (not measured)",
                        "axis from 0",
                        "Fastest end to end",
                        "Equal-time and equal-error",
                        "The GPU model (or a GPU) beside the paper",
                        "<h2>Numerical stability:",
                        "<h2>Provenance</h2>",
                        "revision 1fdf2e5fcaab",
                        "reconstruction"})
    EXPECT_NE(html.find(s), std::string::npos) << s;
  if (image_io_available()) {  // error maps need the PNGs decoded
    EXPECT_NE(html.find("Error maps: |image − reference|"), std::string::npos);
    for (const char* s : {"alt=\"cornell ours error map\"", "alt=\"sibenik noopt error map\""})
      EXPECT_NE(html.find(s), std::string::npos) << s;
    EXPECT_EQ(html.find("alt=\"cornell reference error map\""), std::string::npos);
  }
  EXPECT_EQ(html.find("<script"), std::string::npos) << "self-contained, no scripts";
  EXPECT_EQ(html.find("src=\"http"), std::string::npos) << "no external resources";
  std::string figures;  // the page without its embedded images (base64 text holds any letters)
  for (size_t at = 0, next; at < html.size(); at = html.find('"', next)) {
    next = html.find("base64,", at);
    figures += html.substr(at, next == std::string::npos ? std::string::npos : next - at);
    if (next == std::string::npos) break;
  }
  for (const char* bad : {">nan", "nan<", "nanx", "nan%", "(nan", ">inf", "inf<", "infx", "inf%"})
    EXPECT_EQ(figures.find(bad), std::string::npos) << bad;
  for (const char* s : {"# raycoh report", "### simt[preset=rtx3060] (MODELED GPU (not measured))", "| noopt+mlhcc |",
                        "Fastest end to end:", "## Image quality (PSNR, dB)", "## Provenance"})
    EXPECT_NE(md.find(s), std::string::npos) << s << "\n" << md;
}

TEST(CliReport, BadInputIsAOneLineError) {
  const fs::path dir = temp_dir("cli_report_bad");
  write_file(dir / "other.csv", "a,b\n1,2\n");
  expect_error("report " + (dir / "other.csv").string() + " --out " + (dir / "r.html").string(),
               "other.csv: not a raycoh result CSV");
  expect_error("report " + (dir / "missing.csv").string() + " --out " + (dir / "r.html").string(), "missing.csv");
  write_file(dir / "torn.csv", "scene,pass,method,mray_s\ncornell,primary\n");
  expect_error("report " + (dir / "torn.csv").string() + " --out " + (dir / "r.html").string(),
               "torn.csv line 2: 2 fields, the header has 4");
  EXPECT_FALSE(fs::exists(dir / "r.html"));
}

// Opt-in: RAYCOH_BROWSER_TEST=1 (needs Debian's chromium: apt-get install chromium).
TEST(CliReport, ABrowserLoadsThePageWithoutConsoleMessages) {
  if (!std::getenv("RAYCOH_BROWSER_TEST")) GTEST_SKIP() << "set RAYCOH_BROWSER_TEST=1 to run the headless browser";
  const fs::path dir = render_committed("cli_report_browser");
  const char* shot_env = std::getenv("RAYCOH_BROWSER_SCREENSHOT");
  const fs::path shot = shot_env ? fs::path(shot_env) : dir / "report.png";
  fs::remove(shot);
  const CommandResult r = run_shell(
      "chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --enable-logging=stderr --v=0 "
      "--window-size=1400,2400 --screenshot=" +
      shot.string() + " file://" + (dir / "report.html").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find(":CONSOLE"), std::string::npos) << r.output;
  ASSERT_TRUE(fs::exists(shot)) << r.output;
  EXPECT_GT(fs::file_size(shot), 20000u) << "a blank page";
}

}  // namespace
}  // namespace raycoh::test
