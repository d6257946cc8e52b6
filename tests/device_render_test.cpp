// --device cpu|cuda|cuda:pipeline=fused of `render`, `reference`, `quality` and `converge`: anything else a one-line
// error naming --device; `cuda` (and its fused form) either renders on the device path tracer with its GPU time
// labelled by its clock, or (no CUDA in the build, no device) says why in one line. Without a device: the seams the
// device plugs into (a reference's frames from another renderer and its own cache entry, the converge device clock's
// sums and ratios, the CSV columns and the refusal of a CSV written before them). The device rows themselves:
// tests/gpu_device_rows_test.cpp (label gpu).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "harness/image/device_clock.h"
#include "harness/image/quality.h"
#include "records/converge_row.h"
#include "records/csv.h"
#include "records/quality_row.h"
#include "shading/reference.h"
#include "tests/cli_util.h"
#include "tests/shading_test_util.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;
using test::run_raycoh;
using test::temp_dir;

TEST(DeviceRender, DeviceIsCpuOrCuda) {
  test::expect_error("render --device gpu --res 8x8 --frames 1 --out /tmp/raycoh_device_gpu.pfm", "--device gpu");
  const std::string dir = temp_dir("device_option").string();
  test::expect_error("quality --device gpu --res 16x16 --frames 1 --ref-frames 1 --out " + dir + "/q.csv",
                     "--device gpu: expected cpu, cuda or cuda:pipeline=fused");
  test::expect_error("converge --device tpu --res 16x16 --time 1s --out " + dir + "/c.csv",
                     "--device tpu: expected cpu, cuda or cuda:pipeline=fused");
  test::expect_error("reference --device CUDA --res 16x16 --frames 1 --cache " + dir + "/cache", "--device CUDA");
  // The device path tracer's first bounce is fused or materialized; the `cuda` tracer's other pipelines are not.
  test::expect_error("render --device cuda:pipeline=host --res 8x8 --frames 1 --out /tmp/raycoh_device_host.pfm",
                     "--device cuda:pipeline=host: expected cpu, cuda or cuda:pipeline=fused");
  EXPECT_FALSE(fs::exists(dir + "/q.csv"));
  EXPECT_FALSE(fs::exists(dir + "/c.csv"));
}

TEST(DeviceRender, CudaRendersWithALabelledGpuTimeOrSaysWhyNot) {
  for (const std::string device : {"cuda", "cuda:pipeline=fused"}) {
    SCOPED_TRACE(device);
    const auto out = temp_dir("device_render") / "r.pfm";
    const CommandResult r = run_raycoh("render --device " + device +
                                       " --scene cornell --res 16x16 --frames 2 --force " + "--out " + out.string());
    if (r.exit_code == 0) {
      EXPECT_TRUE(fs::exists(out));
      EXPECT_NE(r.output.find("GPU time"), std::string::npos) << r.output;
      EXPECT_TRUE(r.output.find("measured") != std::string::npos || r.output.find("simulated") != std::string::npos)
          << r.output;
      EXPECT_EQ(r.output.find("first bounce fused") != std::string::npos, device != "cuda") << r.output;
      // Each figure's spread across the 2 frames: [min, max], a 50% interval of the median.
      EXPECT_NE(r.output.find("GPU time per frame median"), std::string::npos) << r.output;
      EXPECT_NE(r.output.find("(50% interval over 2 frames)"), std::string::npos) << r.output;
    } else {
      EXPECT_EQ(r.exit_code, 2) << r.output;
      EXPECT_NE(r.output.find("--device " + device + ": "), std::string::npos) << r.output;
      EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
      EXPECT_FALSE(fs::exists(out));
    }
  }
}

// quality, converge and reference --device cuda where there is no device (or no CUDA): one line, exit 2, nothing
// written. On a machine with a device they run (the gpu tests check their rows).
TEST(DeviceRender, CommandsSayWhyThereIsNoDevice) {
  const fs::path dir = temp_dir("device_none");
  const std::string common = " --device cuda --res 16x16 --max-depth 2 --cache " + (dir / "cache").string();
  for (const std::string& args :
       {"quality --frames 1 --ref-frames 1 --bias-renders 1 --out " + (dir / "q.csv").string() + common,
        "converge --max-frames 1 --time 100s --ref-frames 1 --gpu-model none --out " + (dir / "c.csv").string() +
            common,
        "reference --frames 128 --shard 1/2 --out " + (dir / "p.part").string() + common}) {
    const CommandResult r = run_raycoh(args);
    if (r.exit_code == 0) continue;  // a machine with a device
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find("--device cuda: "), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  }
  if (!fs::exists(dir / "q.csv")) {
    EXPECT_FALSE(fs::exists(dir / "cache"));
  }
}

// A reference made by another renderer (the device's seam, ReferenceRequest::make_renderer) sums its frames in the
// same blocks, and has a cache entry of its own: the CPU's key has no device field, the device's does.
TEST(DeviceRender, DeviceReferenceHasItsOwnEntryAndRenderer) {
  const Scene s = load_scene("cornell");
  const Bvh bvh = build_bvh(s);
  const fs::path dir = temp_dir("device_reference");
  ReferenceRequest cpu;
  cpu.scene_spec = "cornell";
  cpu.settings = test::small(8, 6, 1);
  cpu.frames = 4;
  cpu.frame_block = 2;
  cpu.cache_dir = dir.string();
  cpu.revision = "test";
  EXPECT_FALSE(nlohmann::json::parse(reference_key(cpu)).contains("device"));
  ReferenceRequest dev = cpu;
  dev.device = "cuda";
  EXPECT_NE(test::error_of([&] { get_reference(s, bvh, dev); }).find("no renderer"), std::string::npos);
  int calls = 0;
  dev.make_renderer = [&calls]() -> FrameRenderer {
    return [&calls](uint32_t frame, Accumulator& acc) {
      ++calls;
      for (size_t p = 0; p < acc.sums().size() / 3; ++p) acc.add(p, Vec3(static_cast<float>(frame)));
    };
  };
  EXPECT_EQ(nlohmann::json::parse(reference_key(dev)).at("device"), "cuda");
  const Reference a = get_reference(s, bvh, dev);
  EXPECT_FALSE(a.from_cache);
  EXPECT_EQ(calls, 4);
  EXPECT_FLOAT_EQ(a.image.at(0).x, 1.5f);       // frames 0..3
  EXPECT_FLOAT_EQ(a.first_half.at(5).y, 0.5f);  // frames 0..1
  const Reference again = get_reference(s, bvh, dev);
  EXPECT_TRUE(again.from_cache);
  EXPECT_EQ(calls, 4);  // from the cache: the renderer is not even made
  const Reference c = get_reference(s, bvh, cpu);
  EXPECT_FALSE(c.from_cache);  // the CPU never reads the device's entry
  EXPECT_NE(c.path, a.path);
  // A shard of the device's reference: its part file carries the device's key.
  const fs::path part = dir / "p.part";
  render_reference_part(s, bvh, dev, 1, 2, part.string());
  EXPECT_TRUE(reference_part_done(part.string(), dev, 1, 2));
  EXPECT_FALSE(reference_part_done(part.string(), cpu, 1, 2));
}

// converge --device cuda's third clock: each frame's GPU milliseconds summed on their own, the error curve against
// that sum, and the summary's ratios read on it.
TEST(DeviceRender, DeviceClockSumsFrameTimesAndReadsRatios) {
  DeviceClock base, fast;
  base.label = fast.label = "measured";
  EXPECT_EQ(base.clock_name(), "measured_gpu");
  EXPECT_FALSE(DeviceClock{}.active());
  for (int n = 1; n <= 4; ++n) {
    base.add(2.0, 1.0 / n);  // 2 ms a frame
    fast.add(1.0, 1.0 / n);  // 1 ms a frame, the same error per frame
  }
  EXPECT_DOUBLE_EQ(base.s, 0.008);
  EXPECT_DOUBLE_EQ(fast.last_ms, 1.0);
  ASSERT_EQ(fast.curve.size(), 4u);
  EXPECT_DOUBLE_EQ(fast.curve[2].time, 0.003);
  const CurveComparison cc = compare_curves(fast.curve, base.curve);
  EXPECT_DOUBLE_EQ(cc.horizon, 0.004);
  EXPECT_NEAR(cc.equal_time_error_ratio, 0.5, 1e-12);  // 1/4 against 1/2 at 4 ms
  EXPECT_NEAR(cc.equal_error_speedup, 2.0, 1e-12);     // 1/4 reached at 4 ms against 8 ms
  for (double bad : {-1.0, std::nan(""), HUGE_VAL})
    EXPECT_NE(test::error_of([&] { fast.add(bad, 0.1); }).find("device clock"), std::string::npos);
  EXPECT_EQ(fast.curve.size(), 4u);
}

// The device columns come after every earlier one; a CSV written before them is refused with a line naming the first
// missing column (the rule of every column added since), and --force replaces it.
TEST(DeviceRender, DeviceColumnsAndOlderCsvs) {
  const std::vector<std::string> q = column_names(quality_schema());
  ASSERT_GE(q.size(), 3u);
  EXPECT_EQ(std::vector<std::string>(q.end() - 3, q.end()),
            (std::vector<std::string>{"render_device", "gpu_clock", "gpu_frame_ms"}));
  const std::vector<std::string> c = column_names(converge_schema());
  EXPECT_EQ(std::vector<std::string>(c.end() - 14, c.end()),
            (std::vector<std::string>{"render_device", "gpu_clock", "frame_gpu_ms", "gpu_s", "gpu_camera_ms",
                                      "gpu_generation_ms", "gpu_next_event_ms", "gpu_sample_ms", "gpu_trace_ms",
                                      "gpu_gather_ms", "gpu_first_trace_ms", "gpu_second_trace_ms", "first_wave_rays",
                                      "second_wave_rays"}));
  EXPECT_EQ(column_names(summary_schema()).back(), "render_device");

  const fs::path dir = temp_dir("device_columns");
  QualityOptions o;
  o.common.width = o.common.height = 16;
  o.frames = o.ref_frames = o.bias_renders = 1;
  o.cache_dir = (dir / "cache").string();
  o.out = (dir / "q.csv").string();
  std::string header;  // the columns before the device's (plain names: no quoting needed)
  for (auto it = q.begin(); it != q.end() - 3; ++it) header += (header.empty() ? "" : ",") + *it;
  std::ofstream(o.out) << header << "\n";
  const std::string why = test::error_of([&] { run_quality(o, Provenance{}); });
  EXPECT_NE(why.find("lacks the column 'render_device' and 2 more"), std::string::npos) << why;
  o.common.force = true;
  ASSERT_EQ(run_quality(o, Provenance{}), 0);
  const auto rows = test::read_rows(o.out);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].at("render_device"), "cpu");
  EXPECT_EQ(rows[0].at("gpu_clock"), "");
  EXPECT_EQ(rows[0].at("gpu_frame_ms"), "");
}

}  // namespace
}  // namespace raycoh
