// `raycoh render --device`: cpu or cuda, anything else a one-line error; `cuda` either renders on the device path
// tracer with its GPU time labelled by its clock, or (no CUDA in the build, no device) says why in one line.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tests/cli_util.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

using test::CommandResult;
using test::run_raycoh;
using test::temp_dir;

TEST(DeviceRender, DeviceIsCpuOrCuda) {
  test::expect_error("render --device gpu --res 8x8 --frames 1 --out /tmp/raycoh_device_gpu.pfm", "--device gpu");
}

TEST(DeviceRender, CudaRendersWithALabelledGpuTimeOrSaysWhyNot) {
  const auto out = temp_dir("device_render") / "r.pfm";
  const CommandResult r =
      run_raycoh("render --device cuda --scene cornell --res 16x16 --frames 2 --force --out " + out.string());
  if (r.exit_code == 0) {
    EXPECT_TRUE(std::filesystem::exists(out));
    EXPECT_NE(r.output.find("GPU time"), std::string::npos) << r.output;
    EXPECT_TRUE(r.output.find("measured") != std::string::npos || r.output.find("simulated") != std::string::npos)
        << r.output;
  } else {
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--device cuda"), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(out));
  }
}

}  // namespace
}  // namespace raycoh
