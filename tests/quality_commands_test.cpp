// The quality commands (harness/image/quality.h: render, quality, converge, compare): option validation, CSV rows,
// images, resume, convergence curves.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "core/error.h"
#include "harness/image/compare.h"
#include "harness/image/converge.h"
#include "harness/image/quality.h"
#include "harness/image/render.h"
#include "harness/image/render_cli.h"
#include "records/curves.h"
#include "shading/image.h"
#include "tests/shading_test_util.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

namespace fs = std::filesystem;

using test::error_of;
using test::filled;

TEST(QualityCommands, DurationsAndCurveReadings) {
  EXPECT_DOUBLE_EQ(parse_duration("--time", "60s"), 60.0);
  EXPECT_DOUBLE_EQ(parse_duration("--time", "1.5m"), 90.0);
  EXPECT_DOUBLE_EQ(parse_duration("--time", "500ms"), 0.5);
  EXPECT_DOUBLE_EQ(parse_duration("--time", "2"), 2.0);
  for (const char* bad : {"0", "-5s", "abc", "10parsecs", "inf", ""})
    EXPECT_NE(error_of([&] { parse_duration("--time", bad); }).find("--time"), std::string::npos) << bad;

  // Error 1/t sampled at t = 1, 2, 4: log-linear interpolation is exact for power laws.
  const std::vector<CurvePoint> c = {{1, 1.0}, {2, 0.5}, {4, 0.25}};
  EXPECT_NEAR(error_at_time(c, 2.0), 0.5, 1e-12);
  EXPECT_NEAR(error_at_time(c, std::sqrt(2.0)), 1.0 / std::sqrt(2.0), 1e-12);
  EXPECT_TRUE(std::isnan(error_at_time(c, 0.5)));
  EXPECT_TRUE(std::isnan(error_at_time(c, 5.0)));
  EXPECT_NEAR(time_to_error(c, 0.5), 2.0, 1e-12);
  EXPECT_NEAR(time_to_error(c, 1.0 / std::sqrt(8.0)), std::sqrt(8.0), 1e-12);
  EXPECT_NEAR(time_to_error(c, 2.0), 1.0, 1e-12);  // reached by the first frame
  EXPECT_TRUE(std::isnan(time_to_error(c, 0.1)));
}

TEST(QualityCommands, BadOptionsNameTheOption) {
  const Provenance prov;
  // Each case edits a fresh default option set and expects an error naming the option.
  auto render_error = [&](auto&& edit) {
    RenderOptions o;
    edit(o);
    return error_of([&] { run_render(o, prov); });
  };
  auto quality_error = [&](auto&& edit) {
    QualityOptions o;
    edit(o);
    return error_of([&] { run_quality(o, prov); });
  };
  auto converge_error = [&](auto&& edit) {
    ConvergeOptions o;
    edit(o);
    return error_of([&] { run_converge(o, prov); });
  };
  EXPECT_NE(render_error([](RenderOptions& o) { o.frames = 0; }).find("--frames"), std::string::npos);
  EXPECT_NE(render_error([](RenderOptions& o) { o.crops = {{150, 100, 20, 30}}; }).find("--crop"), std::string::npos);
  EXPECT_NE(render_error([](RenderOptions& o) { o.out = "img.bmp"; }).find("--out"), std::string::npos);
  EXPECT_NE(render_error([](RenderOptions& o) {
              o.generator = {"nosuch", ""};
              o.out = "img.pfm";  // writable in every build
            }).find("valid generators"),
            std::string::npos);
  EXPECT_NE(quality_error([](QualityOptions& o) { o.ref_frames = -1; }).find("--ref-frames"), std::string::npos);
  EXPECT_NE(quality_error([](QualityOptions& o) { o.common.width = 8; }).find("--res"), std::string::npos);
  EXPECT_NE(quality_error([](QualityOptions& o) { o.reference = "/no/such/reference.exr"; }).find("--reference"),
            std::string::npos);
  EXPECT_NE(quality_error([](QualityOptions& o) { o.scenes = {"nosuchscene"}; }).find("--scenes"), std::string::npos);
  EXPECT_NE(quality_error([](QualityOptions& o) {
              o.generators = {{"noopt", ""}, {"noopt", ""}};
            }).find("twice"),
            std::string::npos);
  EXPECT_NE(converge_error([](ConvergeOptions& o) { o.time_s = 0; }).find("--time"), std::string::npos);
  EXPECT_NE(converge_error([](ConvergeOptions& o) {
              o.common.tracer = {"gpu", ""};
            }).find("--tracer"),
            std::string::npos);

  // A reference of the wrong size: a clear error naming both sizes.
  const fs::path dir = test::temp_dir("badref");
  write_image(filled(10, 10, Vec3(0.5f)), (dir / "ref.pfm").string());
  const std::string msg = quality_error([&](QualityOptions& o) {
    o.common.width = 16;
    o.common.height = 12;
    o.reference = (dir / "ref.pfm").string();
    o.out = (dir / "q.csv").string();
  });
  EXPECT_NE(msg.find("10x10"), std::string::npos) << msg;
  EXPECT_NE(msg.find("16x12"), std::string::npos) << msg;
  EXPECT_FALSE(fs::exists(dir / "q.csv.partial"));  // nothing measured, nothing left behind

  CompareOptions cmp;
  cmp.test = (dir / "ref.pfm").string();
  cmp.reference = (dir / "missing.pfm").string();
  EXPECT_NE(error_of([&] { run_compare(cmp); }).find("reference image"), std::string::npos);
  write_image(filled(12, 10, Vec3(0.5f)), (dir / "other.pfm").string());
  cmp.reference = (dir / "other.pfm").string();
  EXPECT_NE(error_of([&] { run_compare(cmp); }).find("sizes differ"), std::string::npos);
}

std::vector<std::string> read_lines(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

TEST(QualityCommands, QualityWritesRowsImagesAndResumes) {
  const fs::path dir = test::temp_dir("quality");
  QualityOptions q;
  q.common.width = 24;
  q.common.height = 16;
  q.frames = 2;
  q.ref_frames = 8;
  q.bias_renders = 2;
  q.cache_dir = (dir / "cache").string();
  q.out = (dir / "q.csv").string();
  q.crops = {{2, 2, 8, 6}};
  Provenance prov;
  prov.git_revision = "test";
  ASSERT_EQ(run_quality(q, prov), 0);
  const auto lines = read_lines(dir / "q.csv");
  ASSERT_EQ(lines.size(), 3u);  // header + noopt + ours
  EXPECT_EQ(lines[0].rfind("scene,scene_spec,", 0), 0u);
  EXPECT_NE(lines[1].find(",noopt,"), std::string::npos);
  EXPECT_NE(lines[2].find(",ours,"), std::string::npos);
  const std::string ext = image_io_available() ? ".png" : ".pfm";
  for (const char* f :
       {"cornell-reference", "cornell-noopt", "cornell-ours", "cornell-ours-crop0", "cornell-reference-crop0"})
    EXPECT_TRUE(fs::exists(dir / "q-images" / (std::string(f) + ext))) << f;
  EXPECT_FALSE(fs::exists(dir / "q.csv.partial"));

  // An interrupted run: its rows sit in the .partial file; the same command takes them and renders nothing.
  fs::rename(dir / "q.csv", dir / "q.csv.partial");
  std::ofstream(dir / "q.csv.partial", std::ios::app) << "cornell,cornell,32,torn";  // a torn last line
  ASSERT_EQ(run_quality(q, prov), 0);
  EXPECT_EQ(read_lines(dir / "q.csv"), lines);

  // Another revision is refused before anything is rendered (its rows would not belong together), and the
  // results already written stay as they were; --force starts afresh.
  fs::rename(dir / "q.csv", dir / "q.csv.partial");
  prov.git_revision = "test2";
  try {
    run_quality(q, prov);
    ADD_FAILURE() << "a partial file of another revision was taken";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("its git_revision is 'test', this run's is 'test2'"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(read_lines(dir / "q.csv.partial"), lines);
  q.common.force = true;
  ASSERT_EQ(run_quality(q, prov), 0);
  const auto redone = read_lines(dir / "q.csv");
  ASSERT_EQ(redone.size(), 3u);
  EXPECT_FALSE(fs::exists(dir / "q.csv.partial"));
}

TEST(QualityCommands, ConvergeWritesCurvesAndRatios) {
  const fs::path dir = test::temp_dir("converge");
  ConvergeOptions c;
  c.common.width = 24;
  c.common.height = 16;
  c.time_s = 0.05;
  c.max_frames = 6;
  c.ref_frames = 8;
  c.cache_dir = (dir / "cache").string();
  c.out = (dir / "c.csv").string();
  ASSERT_EQ(run_converge(c, Provenance{}), 0);
  const auto rows = read_lines(dir / "c.csv");
  EXPECT_GE(rows.size(), 3u);
  EXPECT_LE(rows.size(), 13u);
  const auto summary = read_lines(dir / "c-summary.csv");
  ASSERT_EQ(summary.size(), 4u);  // header + ours (wall) + ours (trace) + ours (modeled_gpu)
  EXPECT_NE(summary[1].find(",wall,"), std::string::npos);
  EXPECT_NE(summary[2].find(",trace,"), std::string::npos);
  EXPECT_NE(summary[3].find(",modeled_gpu,"), std::string::npos);
}

TEST(QualityCommands, RenderWritesImageAndCrops) {
  const fs::path dir = test::temp_dir("render");
  RenderOptions r;
  r.common.width = 20;
  r.common.height = 14;
  r.frames = 2;
  r.out = (dir / "img.pfm").string();
  r.crops = {{0, 0, 5, 5}, {10, 4, 10, 10}};
  ASSERT_EQ(run_render(r, Provenance{}), 0);
  EXPECT_EQ(read_image((dir / "img.pfm").string()).width, 20);
  EXPECT_EQ(read_image((dir / "img-crop1.pfm").string()).width, 10);
  EXPECT_TRUE(fs::exists(dir / "img-crop0.pfm"));
}
}  // namespace
}  // namespace raycoh
