// quality and converge --device cuda on a device (label gpu; skips without one): the rows say where they were
// rendered (render_device cuda, the device's name in `device`, tracer cuda), the GPU time per frame with its clock
// (measured on a GPU, simulated under GPGPU-Sim) and each frame's stages and first two bounces' traces, the converge
// summary reads the device's clock beside the wall clock, and the reference they rendered on the device has a cache
// entry of its own (its key names the device). With the first bounce fused (--device cuda:pipeline=fused) converge's
// errors equal the materialized form's row by row.
// RAYCOH_GPU_TEST_SIZE=sim: 16x16 pixels, 2 frames, paths of 2 scattering events.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cuda/cuda_device.h"
#include "tests/cli_util.h"
#include "tests/gpu_test_size.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

namespace fs = std::filesystem;

#define SKIP_WITHOUT_GPU() \
  if (cuda::device_count() == 0) GTEST_SKIP() << "no CUDA device"

bool is_clock(const std::string& c) { return c == "measured" || c == "simulated"; }
double number(const std::string& text) { return text.empty() ? std::nan("") : std::atof(text.c_str()); }

// One converge row of the device: its clock, the frame by stage (each present, none negative, adding up to at most
// the frame) and the first two bounces' wave traces (parts of the trace stage; each first-wave hit leaves at most
// one second-wave ray).
void expect_device_frame(const std::map<std::string, std::string>& r) {
  EXPECT_TRUE(is_clock(r.at("gpu_clock")));
  EXPECT_GT(number(r.at("frame_gpu_ms")), 0.0);
  double stages = 0;
  for (const char* s : {"camera", "generation", "next_event", "sample", "trace", "gather"}) {
    const double ms = number(r.at(std::string("gpu_") + s + "_ms"));
    EXPECT_GE(ms, 0.0) << s;
    stages += ms;
  }
  EXPECT_LE(stages, number(r.at("frame_gpu_ms")) * 1.001 + 1e-3);
  const double first = number(r.at("gpu_first_trace_ms")), second = number(r.at("gpu_second_trace_ms"));
  EXPECT_GE(first, 0.0);
  EXPECT_GE(second, 0.0);
  EXPECT_LE(first + second, number(r.at("gpu_trace_ms")) * 1.001 + 1e-3);
  EXPECT_GT(number(r.at("first_wave_rays")), 0.0);
  EXPECT_GE(number(r.at("second_wave_rays")), 0.0);
  EXPECT_LE(number(r.at("second_wave_rays")), number(r.at("first_wave_rays")));
}

// The hybrid rule's exposure in device quality rows (noopt, ours on cornell), counted on the device after each
// frame: the CPU quality rows' share, as the batches are equal. common: the device run's options.
void expect_hybrid_share_as_on_the_cpu(const std::vector<std::map<std::string, std::string>>& rows, const fs::path& dir,
                                       const std::string& frames, const std::string& common) {
  ASSERT_EQ(rows.size(), 2u);
  std::string on_cpu = common;
  on_cpu.replace(on_cpu.find("--device cuda"), 13, "--device cpu");
  const std::string cache = (dir / "cache").string();  // the CPU's reference in a cache of its own (checked below)
  on_cpu.replace(on_cpu.find(cache), cache.size(), (dir / "cache-cpu").string());
  const test::CommandResult qc =
      test::run_raycoh("quality --scenes cornell --generators noopt,ours --frames " + frames +
                       " --bias-renders 2 --out " + (dir / "qc.csv").string() + on_cpu);
  ASSERT_EQ(qc.exit_code, 0) << qc.output;
  const auto cpu_rows = test::read_rows(dir / "qc.csv");
  ASSERT_EQ(cpu_rows.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(rows[i].at("hybrid_diffuse_share"), cpu_rows[i].at("hybrid_diffuse_share")) << rows[i].at("method");
  }
  EXPECT_EQ(number(rows[0].at("hybrid_diffuse_share")), 0.0);  // noopt has no groups
  EXPECT_GT(number(rows[1].at("hybrid_diffuse_share")), 0.0);  // cornell's ours has hybrid groups
}

TEST(GpuDeviceRows, QualityAndConvergeRowsOfTheDevice) {
  SKIP_WITHOUT_GPU();
  const fs::path dir = test::temp_dir("gpu_device_rows");
  const std::string frames = std::to_string(test::gpu_test_size(4, 2));
  const std::string common = " --device cuda --res " + std::to_string(test::gpu_test_size(48, 16)) + "x" +
                             std::to_string(test::gpu_test_size(32, 16)) + " --max-depth " +
                             std::to_string(test::gpu_test_size(4, 2)) + " --rr-depth 2 --ref-frames " + frames +
                             " --cache " + (dir / "cache").string();
  const test::CommandResult q = test::run_raycoh("quality --scenes cornell --generators noopt,ours --frames " + frames +
                                                 " --bias-renders 2 --out " + (dir / "q.csv").string() + common);
  ASSERT_EQ(q.exit_code, 0) << q.output;
  const auto rows = test::read_rows(dir / "q.csv");
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& r : rows) {
    EXPECT_EQ(r.at("render_device"), "cuda");
    EXPECT_TRUE(is_clock(r.at("gpu_clock"))) << r.at("gpu_clock");
    EXPECT_GT(number(r.at("gpu_frame_ms")), 0.0);
    EXPECT_NE(r.at("device"), "cpu");
    EXPECT_EQ(r.at("tracer"), "cuda");
    EXPECT_TRUE(std::isfinite(number(r.at("psnr")))) << r.at("psnr");
    EXPECT_TRUE(std::isfinite(number(r.at("rel_mse_ds2")))) << r.at("rel_mse_ds2");
  }
  expect_hybrid_share_as_on_the_cpu(rows, dir, frames, common);

  const test::CommandResult c =
      test::run_raycoh("converge --scene cornell --generators noopt,ours --time 1000s --gpu-model none --max-frames " +
                       frames + " --out " + (dir / "c.csv").string() + common);
  ASSERT_EQ(c.exit_code, 0) << c.output;
  const auto curve = test::read_rows(dir / "c.csv");
  ASSERT_EQ(curve.size(), 2u * std::stoul(frames));
  double last = 0;
  for (const auto& r : curve) {
    EXPECT_EQ(r.at("render_device"), "cuda");
    expect_device_frame(r);
    EXPECT_EQ(r.at("trace_s"), "");  // no trace time apart on the device
    if (r.at("method") == "ours") {
      EXPECT_GT(number(r.at("gpu_s")), last);
      last = number(r.at("gpu_s"));
    }
  }
  const auto summary = test::read_rows(dir / "c-summary.csv");
  ASSERT_EQ(summary.size(), 2u);  // ours against noopt on the wall clock and on the device's
  EXPECT_EQ(summary[0].at("clock"), "wall");
  EXPECT_EQ(summary[1].at("clock"), curve[0].at("gpu_clock") + "_gpu");
  EXPECT_EQ(summary[1].at("render_device"), "cuda");
  EXPECT_GT(number(summary[1].at("horizon_s")), 0.0);

  // quality rendered the reference on the device and converge read it from the cache.
  EXPECT_NE(c.output.find("cached"), std::string::npos) << c.output;

  // The first bounce fused: the same images bit for bit (its reference too, in an entry of its own), so the same
  // errors frame by frame; the rows name the form.
  std::string fused_common = common;
  fused_common.replace(fused_common.find("--device cuda"), 13, "--device cuda:pipeline=fused");
  const test::CommandResult f =
      test::run_raycoh("converge --scene cornell --generators noopt,ours --time 1000s --gpu-model none --max-frames " +
                       frames + " --out " + (dir / "f.csv").string() + fused_common);
  ASSERT_EQ(f.exit_code, 0) << f.output;
  const auto fused = test::read_rows(dir / "f.csv");
  ASSERT_EQ(fused.size(), curve.size());
  for (size_t i = 0; i < fused.size(); ++i) {
    EXPECT_EQ(fused[i].at("render_device"), "cuda:pipeline=fused");
    expect_device_frame(fused[i]);
    EXPECT_EQ(fused[i].at("method"), curve[i].at("method"));
    EXPECT_EQ(fused[i].at("rel_mse"), curve[i].at("rel_mse")) << "row " << i;
    EXPECT_EQ(fused[i].at("first_wave_rays"), curve[i].at("first_wave_rays")) << "row " << i;
    EXPECT_EQ(fused[i].at("second_wave_rays"), curve[i].at("second_wave_rays")) << "row " << i;
  }
  // One cache entry per form, each key naming its device.
  std::vector<std::string> devices;
  for (const auto& e : fs::directory_iterator(dir / "cache"))
    if (e.path().extension() == ".json") {
      std::ifstream in(e.path());
      devices.push_back(nlohmann::json::parse(in).at("key").at("device"));
    }
  std::sort(devices.begin(), devices.end());
  EXPECT_EQ(devices, (std::vector<std::string>{"cuda", "cuda:pipeline=fused"}));
}

}  // namespace
}  // namespace raycoh
