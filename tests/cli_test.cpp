// The command line as a user meets it: exit codes, one-line errors naming the input; list, scenes info, rays.
// The experiment and rendering commands have their own files (cli_experiment_test.cpp, cli_rendering_test.cpp).
#include <gtest/gtest.h>

#include "tests/cli_util.h"
#include "tests/scenes_test_util.h"

namespace raycoh::test {
namespace {

TEST(Cli, BadNamesAndValuesExitWithCode2AndNameTheChoices) {
  expect_error("table --generators nope --res 8x8 --frames 1", "valid generators: noopt");
  expect_error("table --tracers nope --res 8x8 --frames 1", "valid tracers: cpu, embree");
  expect_error("table --tracers embree:mode=warp --res 8x8 --frames 1", "single");
  expect_error("table --res 0x10", "--res");
  expect_error("table --res abc", "--res");
  expect_error("table --frames 0", "--frames");
  expect_error("table --scenes /no/such/file.glb --res 8x8", "/no/such/file.glb");
  expect_error("table --scenes voxels:size=2 --res 8x8 --frames 1", "size");
  expect_error("scenes info /no/such.obj", "/no/such.obj");
  expect_error("frobnicate", "frobnicate");
  expect_error("rays --scene cornell --generator nope --out /tmp/x.csv", "valid generators");
  expect_error("table --generators ours:k=65 --res 8x8", "k=65");
  expect_error("table --generators ours:kk=2 --res 8x8", "valid parameters: tile, k, order, seed");
}

TEST(Cli, ARunWhoseCameraSeesNothingFailsClearly) {
  GltfWriter w = one_triangle();
  // The camera at z = 5 looks down +z, away from the triangle at z = 0.
  w.cameras = R"([{"type":"perspective","perspective":{"yfov":0.5,"znear":0.1}}])";
  w.nodes = R"([{"mesh":0},{"camera":0,"translation":[0,0,5],"rotation":[0,1,0,0]}])";
  w.scenes = R"([{"nodes":[0,1]}])";
  const std::string file = w.write("cli_no_hits", "away.glb").string();
  const std::string out = temp_dir("cli_no_hits").string() + "/t.csv";
  expect_error(fmt::format("table --scenes {} --tracers cpu --res 8x8 --frames 1 --out {}", file, out),
               "camera sees no triangle");
}

TEST(Cli, ListNamesEveryPlugin) {
  const CommandResult r = run_raycoh("list");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* s : {"noopt", "none", "cpu", "embree", "cornell", "voxels", "stream_coherent"})
    EXPECT_NE(r.output.find(s), std::string::npos) << s;
}

TEST(Cli, RaysDumpsOneRowPerRay) {
  const auto out = temp_dir("cli_rays") / "rays.csv";
  const CommandResult r = run_raycoh("rays --scene cornell --res 16x16 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(out);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("index,pixel_x,pixel_y,frame,org_x", 0), 0u) << header;
  EXPECT_GT(count_lines(out), 100);
}

}  // namespace
}  // namespace raycoh::test
