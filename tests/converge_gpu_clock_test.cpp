// The modeled GPU clock of `converge` (harness/image/gpu_clock.h): the frame model on the renderer's rays, the modeled
// columns of the converge CSV, and the equal-time / equal-error reading on every clock.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>

#include "bvh/bvh_build.h"
#include "harness/image/converge.h"
#include "harness/image/gpu_clock.h"
#include "plugins/tracer_registry.h"
#include "records/csv.h"
#include "records/curves.h"
#include "scenes/scene.h"
#include "tests/cli_util.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

namespace fs = std::filesystem;
using test::read_rows;

// Power-law curves: error A / frames after each of n frames, each frame `dt` long on the clock.
std::vector<CurvePoint> power_law(double a, double dt, int n) {
  std::vector<CurvePoint> c;
  for (int f = 1; f <= n; ++f) c.push_back({f * dt, a / f});
  return c;
}

TEST(ConvergeGpuClock, EqualTimeAndEqualErrorOnEitherClock) {
  // Per frame, ours is 1.2x NoOpt's error. On the CPU both frames take 10 ms; on the GPU NoOpt's takes 2 ms and
  // ours 1 ms. Error against time is then A dt / t: the equal-time ratio is (1.2 dt_ours) / (1 dt_noopt) and the
  // equal-error speedup its inverse.
  const int n = 64;
  const CurveComparison cpu = compare_curves(power_law(1.2, 0.010, n), power_law(1.0, 0.010, n));
  EXPECT_NEAR(cpu.equal_time_error_ratio, 1.2, 1e-9);
  EXPECT_NEAR(cpu.equal_error_speedup, 1.0 / 1.2, 1e-9);
  EXPECT_NEAR(cpu.horizon, n * 0.010, 1e-12);
  const CurveComparison gpu = compare_curves(power_law(1.2, 0.001, n), power_law(1.0, 0.002, n));
  EXPECT_NEAR(gpu.equal_time_error_ratio, 0.6, 1e-9);
  EXPECT_NEAR(gpu.equal_error_speedup, 1.0 / 0.6, 1e-9);
  EXPECT_NEAR(gpu.horizon, n * 0.001, 1e-12);  // the shorter curve's last time
  EXPECT_NEAR(gpu.target_error, 1.2 / n, 1e-15);
  EXPECT_NEAR(gpu.baseline_time, 0.002 * n / 1.2, 1e-12);
}

TEST(ConvergeGpuClock, FrameModelTimesTheRenderersRays) {
  Scene scene = load_scene("cornell");
  const Bvh bvh = build_bvh(scene);
  auto cpu = make_tracer({"cpu", ""}, scene, bvh);
  auto simt = make_tracer({"simt", ""}, scene, bvh);
  RenderSettings rs;
  rs.width = 24;
  rs.height = 16;
  auto gen = make_generator({"ours", ""});
  PathTracer pt(scene, *cpu, *gen, rs);
  Accumulator acc(rs.width, rs.height);
  const FrameStats timed = pt.render_frame(3, acc);
  FrameModel a(scene, *cpu, *simt, make_generator({"ours", ""}), rs);
  FrameModel b(scene, *cpu, *simt, make_generator({"ours", ""}), rs);
  const ModeledFrame ma = a.model(3, timed);
  EXPECT_GT(ma.trace_ms, 0.0);
  EXPECT_GT(ma.gen_ms, 0.0);
  EXPECT_GE(ma.launches, 3);                   // camera rays, the generator's batch, shadow rays at least
  EXPECT_EQ(b.model(3, timed).ms(), ma.ms());  // deterministic: no measured time in it
}

ConvergeOptions tiny_converge(const fs::path& dir, const std::string& out) {
  ConvergeOptions c;
  c.common.width = 24;
  c.common.height = 16;
  c.time_s = 100;
  c.max_frames = 4;
  c.ref_frames = 4;
  c.cache_dir = (dir / "cache").string();
  c.out = (dir / out).string();
  return c;
}

double num(const std::map<std::string, std::string>& r, const std::string& col) { return std::stod(r.at(col)); }

TEST(ConvergeGpuClock, ModeledColumnsArePositiveMonotoneAndNeverMeasured) {
  const fs::path dir = test::temp_dir("converge_gpu");
  ConvergeOptions c = tiny_converge(dir, "a.csv");
  c.model_every = 2;
  ASSERT_EQ(run_converge(c, Provenance{}), 0);
  ConvergeOptions again = tiny_converge(dir, "b.csv");
  again.model_every = 2;
  ASSERT_EQ(run_converge(again, Provenance{}), 0);
  const auto rows = read_rows(dir / "a.csv"), rows2 = read_rows(dir / "b.csv");
  ASSERT_EQ(rows.size(), 8u);  // 2 generators x 4 frames
  ASSERT_EQ(rows2.size(), rows.size());
  std::map<std::string, double> last_s, last_frame_ms;
  for (size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    const std::string m = r.at("method");
    EXPECT_NE(r.at("gpu_model").find("simt[preset=rtx3060"), std::string::npos);
    const int frame = std::stoi(r.at("frame"));
    EXPECT_EQ(r.at("modeled_frame"), (frame - 1) % 2 == 0 ? "1" : "0");
    const double frame_ms = num(r, "frame_modeled_gpu_ms");
    EXPECT_GT(frame_ms, 0.0);
    // (the CSV holds 6 significant digits)
    EXPECT_NEAR(frame_ms, num(r, "frame_modeled_gen_ms") + num(r, "frame_modeled_trace_ms"), 1e-5 * frame_ms);
    if (r.at("modeled_frame") == "0") {
      EXPECT_EQ(frame_ms, last_frame_ms[m]);  // held from the last modeled
    }
    // Cumulative: strictly increasing, and exactly the sum of the frames' modeled times (nothing measured in it).
    const double s = num(r, "modeled_gpu_s");
    EXPECT_GT(s, last_s[m]);
    EXPECT_NEAR(s, last_s[m] + frame_ms * 1e-3, 1e-5 * s);
    last_s[m] = s;
    last_frame_ms[m] = frame_ms;
    // Independent of the measured clock: the same command again models the same times to the bit, while its
    // measured times are its own.
    for (const char* col : {"frame_modeled_gen_ms", "frame_modeled_trace_ms", "frame_modeled_gpu_ms", "modeled_gpu_s"})
      EXPECT_EQ(r.at(col), rows2[i].at(col)) << col;
    EXPECT_GT(num(r, "wall_s"), 0.0);
  }
  const auto summary = read_rows(dir / "a-summary.csv");
  ASSERT_EQ(summary.size(), 3u);  // ours against noopt on wall, trace, modeled_gpu
  EXPECT_EQ(summary[2].at("clock"), "modeled_gpu");
  EXPECT_NEAR(num(summary[2], "horizon_s"), std::min(last_s["noopt"], last_s["ours"]), 1e-12);
  EXPECT_GT(num(summary[2], "equal_time_error_ratio"), 0.0);
}

TEST(ConvergeGpuClock, NoModelNoModeledColumns) {
  const fs::path dir = test::temp_dir("converge_nogpu");
  ConvergeOptions c = tiny_converge(dir, "c.csv");
  c.max_frames = 2;
  c.gpu_model = "none";
  ASSERT_EQ(run_converge(c, Provenance{}), 0);
  for (const auto& r : read_rows(dir / "c.csv")) {
    EXPECT_EQ(r.at("modeled_gpu_s"), "");
    EXPECT_EQ(r.at("gpu_model"), "");
  }
  EXPECT_EQ(read_rows(dir / "c-summary.csv").size(), 2u);
  c.gpu_model = "cpu";
  EXPECT_NE(test::error_of([&] { run_converge(c, Provenance{}); }).find("--gpu-model cpu"), std::string::npos);
  c.gpu_model = "simt";
  c.model_every = 0;
  EXPECT_NE(test::error_of([&] { run_converge(c, Provenance{}); }).find("--model-every"), std::string::npos);
}

}  // namespace
}  // namespace raycoh
