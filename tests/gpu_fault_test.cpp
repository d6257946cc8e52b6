// CUDA errors injected where they happen (RAYCOH_INJECT_FAULT on a CUDA call, cuda/cuda_check.cuh): an allocation
// failure, a launch failure and a kernel that does not finish each end a `cuda` table with one line naming the
// scene, method or pass and stage and the failing call, exit 1, keep every finished row, and the same command
// resumes. Small (32x24) so that it runs under GPGPU-Sim too; skips cleanly without a GPU. Label `gpu`.
#include <gtest/gtest.h>

#include <string>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "core/fault_injection.h"
#include "cuda/cuda_device.h"
#include "cuda/trace_kernels.h"
#include "scenes/scene.h"
#include "tests/cli_util.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

TEST(GpuFault, AnInjectedAllocationFailureIsADeviceFault) {
  if (cuda::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  const Scene scene = load_scene("cornell");
  const Bvh bvh = build_bvh(scene);
  set_fault_injection("cudaMalloc:1");
  try {
    cuda::DeviceTracer tracer(bvh.view());
    ADD_FAILURE() << "no fault";
  } catch (const DeviceFault& e) {
    EXPECT_NE(std::string(e.what()).find("cudaMalloc"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("injected"), std::string::npos) << e.what();
  }
  set_fault_injection("");
}

// `site` fails at its n-th check: exit 1, one line naming the call, rows kept, and the same command completes.
void expect_fault_resumes(const std::string& site, const std::string& call) {
  const auto dir = test::temp_dir("gpu_fault");
  const std::string out = (dir / (call + ".csv")).string();
  const std::string args =
      "table --scenes cornell --generators noopt,ours --encoders none,origin --tracers cuda "
      "--res 32x24 --frames 1 --repeat 2 --force --out " +
      out;
  const test::CommandResult broken = test::run_shell("RAYCOH_INJECT_FAULT=" + site + " $R " + args);
  EXPECT_EQ(broken.exit_code, 1) << broken.output;
  EXPECT_NE(broken.output.find("raycoh: device fault: scene cornell"), std::string::npos) << broken.output;
  EXPECT_NE(broken.output.find(call), std::string::npos) << broken.output;
  const std::string resume_args =
      "table --scenes cornell --generators noopt,ours --encoders none,origin --tracers "
      "cuda --res 32x24 --frames 1 --repeat 2 --out " +
      out;
  const test::CommandResult resumed = test::run_raycoh(resume_args);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_EQ(test::count_lines(out), 1 + 1 + 4);  // header, primary, four methods
}

TEST(GpuFault, ALaunchFailureKeepsTheRowsAndResumes) {
  if (cuda::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  expect_fault_resumes("cudaGetLastError:12", "cudaGetLastError");
}

TEST(GpuFault, AKernelThatDoesNotFinishKeepsTheRowsAndResumes) {
  if (cuda::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  expect_fault_resumes("cudaEventSynchronize:9", "cudaEventSynchronize");
}

}  // namespace
}  // namespace raycoh
