// Every input a fuzzer once found (tests/fuzz/regressions/<target>/) and every hand-written seed
// (tests/fuzz/seeds/<target>/), run through its fuzz target's function (tests/fuzz/fuzz_targets.h) in the ordinary
// suite: the reader must answer each with a result or a one-line raycoh::Error naming the input, never a crash or
// another exception. Under scripts/sanitize the same inputs run with ASan + UBSan.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "shading/reference.h"
#include "tests/fuzz/fuzz_targets.h"
#include "tests/test_util.h"

namespace fs = std::filesystem;

namespace {

std::vector<fs::path> inputs_of(const std::string& folder, const std::string& target) {
  const fs::path dir = fs::path(RAYCOH_SOURCE_DIR) / "tests" / "fuzz" / folder / target;
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

void run_inputs(const std::string& folder, size_t& count) {
  for (const raycoh::fuzz::Target& t : raycoh::fuzz::targets()) {
    for (const fs::path& file : inputs_of(folder, t.name)) {
      SCOPED_TRACE(file.string());
      std::ifstream in(file, std::ios::binary);
      const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      EXPECT_NO_THROW(t.run(bytes.data(), bytes.size())) << t.name;
      ++count;
    }
  }
}

}  // namespace

TEST(FuzzRegressions, EveryKeptInputGetsAResultOrAOneLineError) {
  size_t count = 0;
  run_inputs("regressions", count);
  std::printf("%zu regression inputs\n", count);
}

TEST(FuzzRegressions, EveryHandWrittenSeedGetsAResultOrAOneLineError) {
  size_t count = 0;
  run_inputs("seeds", count);
  EXPECT_GT(count, 0u);
}

TEST(FuzzRegressions, EveryTargetHasSeedsAndAUniqueName) {
  std::vector<std::string> names;
  for (const raycoh::fuzz::Target& t : raycoh::fuzz::targets()) {
    names.push_back(t.name);
    EXPECT_EQ(raycoh::fuzz::find_target(t.name), &t);
    EXPECT_FALSE(inputs_of("seeds", t.name).empty()) << "tests/fuzz/seeds/" << t.name << " has no seed";
  }
  std::sort(names.begin(), names.end());
  EXPECT_EQ(std::adjacent_find(names.begin(), names.end()), names.end());
}

// The CLI's side of a fixed finding: exit 2 and one line naming the file, no allocation of the header's size.
TEST(FuzzRegressions, CompareRefusesAPfmWhoseHeaderClaimsMoreThanItHolds) {
  const fs::path dir = raycoh::test::temp_dir("fuzz_regressions_compare");
  raycoh::test::write_file(dir / "huge.pfm", std::string("PF\n65536 65536\n-1.0\n") + std::string(12, '\0'));
  raycoh::test::write_file(dir / "small.pfm", std::string("PF\n1 1\n-1.0\n") + std::string(12, '\0'));
  const auto r =
      raycoh::test::run_raycoh("compare " + (dir / "huge.pfm").string() + " " + (dir / "small.pfm").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("huge.pfm: truncated PFM"), std::string::npos) << r.output;
}

// A sidecar whose frame count is a float out of int's range: get<int> was undefined behaviour (UBSan under
// scripts/sanitize); now the frame count is unknown (0).
TEST(FuzzRegressions, ASidecarFrameCountOutOfIntRangeIsUnknown) {
  const fs::path dir = raycoh::test::temp_dir("fuzz_regressions_sidecar");
  raycoh::test::write_file(dir / "ref.pfm", std::string("PF\n1 1\n-1.0\n") + std::string(12, '\0'));
  for (const char* frames : {"1e300", "-1e300", "4294967297", "2.5"}) {
    raycoh::test::write_file(dir / "ref.json", std::string(R"({"image":"ref.pfm","key":{"frames":)") + frames + "}}");
    EXPECT_EQ(raycoh::reference_file_frames((dir / "ref.pfm").string()), 0) << frames;
  }
}
