// Device faults lose nothing: RAYCOH_INJECT_FAULT (core/fault_injection.h) makes a chosen check fail; the run ends
// with one line naming the scene, frame, method or pass, tracer and stage, exits 1, keeps every finished row in
// <out>.partial, and the same command resumes and completes the file. Here the experiment loop's `trace` site (any
// tracer, no GPU needed); tests/gpu_fault_test.cpp injects CUDA errors on a GPU or under GPGPU-Sim.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "core/error.h"
#include "core/fault_injection.h"
#include "tests/cli_util.h"
#include "tests/test_util.h"

namespace raycoh::test {
namespace {

TEST(FaultInjection, FiresOnceAtTheNthMatchingSite) {
  set_fault_injection("trace:2");
  EXPECT_FALSE(inject_fault("cudaMalloc(&ptr_, sizeof(T) * want)"));
  EXPECT_FALSE(inject_fault("trace"));
  EXPECT_TRUE(inject_fault("trace"));
  EXPECT_FALSE(inject_fault("trace"));
  set_fault_injection("cudaMalloc:1");
  EXPECT_TRUE(inject_fault("cudaMalloc(&ptr_, sizeof(T) * want)"));
  for (const char* bad : {"trace", "trace:0", ":3", "trace:x", "trace:-1"})
    EXPECT_THROW(set_fault_injection(bad), Error) << bad;
  set_fault_injection("");
  EXPECT_FALSE(inject_fault("trace"));
}

std::vector<std::string> error_lines(const std::string& output) {
  std::vector<std::string> lines;
  size_t at = 0;
  while ((at = output.find("raycoh: ", at)) != std::string::npos) {
    const size_t end = output.find('\n', at);
    lines.push_back(output.substr(at, end - at));
    at = end;
  }
  return lines;
}

TEST(DeviceFault, AFaultKeepsEveryFinishedRowAndTheSameCommandResumes) {
  const auto dir = temp_dir("device_fault");
  const std::string args =
      "table --scenes cornell --generators noopt,ours --tracers cpu --res 32x24 --frames 2 "
      "--repeat 2 --out ";
  const CommandResult whole = run_raycoh(args + (dir / "whole.csv").string());
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  // Traces: frame 0 primary, noopt, ours; frame 1 primary, noopt (the 5th), ours.
  const std::string out = (dir / "t.csv").string();
  const CommandResult broken = run_shell("RAYCOH_INJECT_FAULT=trace:5 $R " + args + out);
  EXPECT_EQ(broken.exit_code, 1) << broken.output;
  const std::vector<std::string> lines = error_lines(broken.output);
  ASSERT_EQ(lines.size(), 1u) << broken.output;
  for (const char* s : {"raycoh: device fault: scene cornell, frame 1, method noopt, tracer cpu, trace: injected",
                        "4 rows measured so far are kept in", "run the same command again to resume"})
    EXPECT_NE(lines[0].find(s), std::string::npos) << s << "\n" << lines[0];
  const std::vector<std::string> kept = read_lines(out + ".partial");
  ASSERT_EQ(kept.size(), 1u + 4u);  // header and the four finished rows
  const CommandResult resumed = run_raycoh(args + out);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("resuming: 4 rows already measured"), std::string::npos) << resumed.output;
  const std::vector<std::string> done = read_lines(out);
  EXPECT_EQ(done.size(), read_lines(dir / "whole.csv").size());
  for (const std::string& row : kept) EXPECT_NE(std::find(done.begin(), done.end(), row), done.end()) << row;
}

}  // namespace
}  // namespace raycoh::test
