// `raycoh stability` (harness/stability.h) on the stiff-case catalogue: each catalogue scene's expected result
// (which gated cases fail, and the rates that must stay exactly zero) is held here at a small resolution; the
// command's exit code follows the thresholds (0, 3) and bad input is exit 2.
#include "harness/stability.h"

#include <gtest/gtest.h>

#include <set>

#include "scenes/scene.h"
#include "tests/cli_util.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

StabilityOptions small_options() {
  StabilityOptions o;
  o.width = 48;
  o.height = 36;
  o.generators = {{"noopt", ""}, {"ours", ""}};
  return o;
}

std::set<std::string> failing_cases(const StabilityReport& r) {
  std::set<std::string> names;
  for (const StabilityCase& c : r.cases)
    if (c.failed()) names.insert(c.name);
  return names;
}

struct Expected {
  const char* spec;
  std::set<std::string> failing;
};

// The catalogue's expected results (docs/stability.md has the reasons).
const Expected kCatalogue[] = {
    {"far:offset=0", {}},   {"far:offset=1e3", {}},    {"far:offset=1e5", {}},
    {"far:offset=1e7", {}}, {"scaled:scale=1e-4", {}}, {"scaled:scale=1e4", {}},
    {"slivers", {}},        {"coplanar", {}},          {"flat", {}},
    {"grazing", {}},        {"pile:tris=256", {}},
};

TEST(Stability, CatalogueScenesGiveTheirExpectedResults) {
  const StabilityOptions o = small_options();
  for (const Expected& e : kCatalogue) {
    const StabilityReport r = measure_stability(e.spec, o);
    EXPECT_EQ(failing_cases(r), e.failing) << e.spec;
    for (const StabilityCase& c : r.cases) {
      // Whatever the scene, the float traversal agrees with the reference and no ray is non-finite.
      if (c.name == "wrong_closest_hit" || c.name == "missed_hit" || c.name == "non_finite") {
        EXPECT_EQ(c.count, 0u) << e.spec << " " << c.batch << " " << c.name;
      }
      if (c.name == "self_intersection") {
        EXPECT_GT(c.of, 100u) << e.spec << " " << c.batch;
      }
    }
  }
}

// Origin rebasing (scenes/scene.h): the far and scaled scenes are moved and scaled exactly; scenes near the
// origin at a usual size are left alone.
TEST(Stability, FarAndTinyScenesAreRebasedExactly) {
  const Scene near = load_scene("far:offset=0"), far = load_scene("far:offset=1e7");
  EXPECT_EQ(near.rebase_scale, 1.f);
  EXPECT_EQ(near.rebase_offset.x, 0.f);
  ASSERT_EQ(far.positions.size(), near.positions.size());
  const Vec3 shift = far.rebase_offset - Vec3(1e7f);  // the content's own box centre
  EXPECT_GT(shift.x, 0.f);
  for (size_t i = 0; i < near.positions.size(); ++i) {
    const Vec3 d = far.positions[i] - (near.positions[i] - shift);
    ASSERT_EQ(d.x, 0.f) << i;
    ASSERT_EQ(d.y, 0.f) << i;
    ASSERT_EQ(d.z, 0.f) << i;
  }
  const Scene tiny = load_scene("scaled:scale=1e-4");
  EXPECT_EQ(tiny.rebase_scale, 512.f);  // a box of 2.2e-3 scaled into [1, 2)
  EXPECT_EQ(load_scene("cornell").rebase_scale, 1.f);
  EXPECT_EQ(load_scene("cornell").rebase_offset.y, 0.f);
  EXPECT_EQ(load_scene("scaled:scale=1e4").rebase_scale, 1.f);
}

// Rebased, the scene 1e7 from the origin traces like the one at the origin: the same rays hit and miss.
TEST(Stability, FarSceneMatchesTheOneAtTheOrigin) {
  const StabilityOptions o = small_options();
  const StabilityReport a = measure_stability("far:offset=0", o), b = measure_stability("far:offset=1e7", o);
  ASSERT_EQ(a.cases.size(), b.cases.size());
  for (size_t i = 0; i < a.cases.size(); ++i) {
    EXPECT_EQ(a.cases[i].of, b.cases[i].of) << a.cases[i].batch << " " << a.cases[i].name;
    if (a.cases[i].name.rfind("key_degeneracy", 0) != 0) {
      EXPECT_EQ(a.cases[i].count, b.cases[i].count) << a.cases[i].batch << " " << a.cases[i].name;
    }
  }
}

TEST(Stability, CornellPassesAndReportsEveryCase) {
  const StabilityReport r = measure_stability("cornell", small_options());
  EXPECT_FALSE(r.failed());
  for (const char* name : {"non_finite", "wrong_closest_hit", "missed_hit"})
    EXPECT_NE(r.find("primary", name), nullptr);
  for (const std::string& name : stability_case_names()) {
    if (name == "key_degeneracy" || name == "wrong_closest_hit" || name == "missed_hit" || name == "non_finite")
      continue;
    EXPECT_NE(r.find("ours", name), nullptr) << name;
  }
  EXPECT_EQ(r.find("noopt", "reuse_discontinuity"), nullptr);  // noopt reuses nothing
  EXPECT_NE(r.find("ours", "key_degeneracy:origin"), nullptr);
  EXPECT_NE(r.find("ours", "key_degeneracy:twopoint"), nullptr);
}

TEST(Stability, ExitCodeFollowsThresholds) {
  test::CommandResult ok = test::run_raycoh("stability --scene cornell --res 32x24 --generators noopt");
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_NE(ok.output.find("| noopt | self_intersection |"), std::string::npos) << ok.output;
  // The direct generator reuses world directions, some below the geometric surface: a zero threshold fails it.
  test::CommandResult fail = test::run_raycoh(
      "stability --scene cornell --res 32x24 --generators direct --threshold below_geometric_surface=0");
  EXPECT_EQ(fail.exit_code, 3) << fail.output;
  EXPECT_NE(fail.output.find("| below_geometric_surface |"), std::string::npos);
  EXPECT_NE(fail.output.find("FAIL"), std::string::npos);
  // A looser threshold lets a failing case pass.
  test::CommandResult loose = test::run_raycoh(
      "stability --scene cornell --res 32x24 --generators direct --threshold below_geometric_surface=1");
  EXPECT_EQ(loose.exit_code, 0) << loose.output;
}

TEST(Stability, WritesCsvAndRefusesBadInput) {
  const auto dir = test::temp_dir("stability_csv");
  const std::string out = (dir / "s.csv").string();
  test::CommandResult r = test::run_raycoh("stability --scene cornell --res 16x12 --generators ours --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto lines = test::read_lines(out);
  ASSERT_GT(lines.size(), 10u);
  EXPECT_EQ(lines[0].rfind("scene,scene_spec,scene_triangles,batch,case,count,of,rate,threshold,status", 0), 0u)
      << lines[0];
  test::expect_error("stability --scene cornell --res 16x12 --out " + out, "already exists");
  test::expect_error("stability --scene no_such_scene", "no_such_scene");
  test::expect_error("stability --scene cornell --res 0x5", "--res");
  test::expect_error("stability --scene cornell --generators sideways", "sideways");
  test::expect_error("stability --scene cornell --encoders zorder", "zorder");
  test::expect_error("stability --scene cornell --threshold speed=1", "unknown case 'speed'");
  test::expect_error("stability --scene cornell --threshold self_intersection=2", "RATE in [0, 1]");
}

}  // namespace
}  // namespace raycoh
