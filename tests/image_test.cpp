// Images: accumulation with NaN/Inf counting, tone map, crops, and the PFM/EXR/PNG files (shading/image.h).
#include "shading/image.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "tests/shading_test_util.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

namespace fs = std::filesystem;

using test::error_of;
using test::test_pattern;

TEST(Accumulator, CountsNonFiniteSamplesInsteadOfAddingThem) {
  Accumulator acc(2, 1);
  acc.add(0, {1.f, 2.f, 3.f});
  acc.add(0, {3.f, 2.f, 1.f});
  acc.add(0, {NAN, 0.f, 0.f});
  acc.add(1, {INFINITY, 0.f, 0.f});
  acc.add(1, {0.f, -INFINITY, 0.f});
  const Image m = acc.mean();
  EXPECT_EQ(m.at(0).x, 2.f);
  EXPECT_EQ(m.at(0).y, 2.f);
  EXPECT_EQ(m.at(0).z, 2.f);
  EXPECT_EQ(m.at(1).x, 0.f);  // no finite sample: 0, not NaN
  EXPECT_EQ(acc.non_finite_samples(), 3u);
  EXPECT_EQ(acc.non_finite_samples(0), 1u);
  EXPECT_EQ(acc.non_finite_samples(1), 2u);
  EXPECT_EQ(acc.pixels_with_non_finite(), 2u);
  EXPECT_EQ(acc.samples(0), 2u);
  for (float v : m.rgb) EXPECT_TRUE(std::isfinite(v));
}

TEST(ToneMap, MonotoneBoundedAndDefinedForNonFinite) {
  for (ToneMapKind kind : {ToneMapKind::Aces, ToneMapKind::Clamp}) {
    for (float exposure : {0.25f, 1.f, 4.f}) {
      const ToneMap tm{kind, exposure};
      float prev = -1.f;
      for (float x = 0.f; x < 200.f; x = x * 1.05f + 1e-4f) {
        const float y = tone_map_channel(x, tm);
        EXPECT_GE(y, prev) << "x " << x;
        EXPECT_GE(y, 0.f);
        EXPECT_LE(y, 1.f);
        prev = y;
      }
      EXPECT_EQ(tone_map_channel(0.f, tm), 0.f);
      EXPECT_EQ(tone_map_channel(-3.f, tm), 0.f);
      EXPECT_EQ(tone_map_channel(NAN, tm), 0.f);
      EXPECT_EQ(tone_map_channel(INFINITY, tm), 1.f);
    }
  }
  EXPECT_EQ(srgb_oetf(1.f), 1.f);
  EXPECT_NEAR(srgb_oetf(0.5f), 0.735357f, 1e-5f);   // IEC 61966-2-1
  EXPECT_NEAR(srgb_oetf(0.002f), 0.02584f, 1e-6f);  // linear segment
  EXPECT_THROW(parse_tone_map("filmic"), Error);
}

TEST(ToneMap, AutoExposureMapsTheLogAverageToMiddleGrey) {
  Image img(4, 1, Vec3(0.f));  // black pixels (background) do not count
  img.set(0, Vec3(0.01f));
  img.set(1, Vec3(1.f));
  const float e = auto_exposure(img);
  EXPECT_NEAR(e, 0.18f / 0.1f, 1e-4f);  // log-average of 0.01 and 1 is 0.1
  const ToneMap tm = resolved(ToneMap{ToneMapKind::Aces, 1.f, true}, img);
  EXPECT_FALSE(tm.auto_exposure);
  EXPECT_EQ(tm.exposure, e);
  EXPECT_EQ(resolved(ToneMap{ToneMapKind::Clamp, 2.f, false}, img).exposure, 2.f);
  EXPECT_EQ(auto_exposure(Image(3, 3, Vec3(0.f))), 1.f);
  EXPECT_NE(describe(ToneMap{ToneMapKind::Aces, 1.f, true}).find("exposure=auto"), std::string::npos);
}

TEST(Crop, ParsesValidatesAndCopies) {
  const Crop c = parse_crop("--crop", "1,2,3,4");
  EXPECT_EQ(c.x, 1);
  EXPECT_EQ(c.h, 4);
  EXPECT_NE(error_of([] { parse_crop("--crop", "1,2,3"); }).find("--crop"), std::string::npos);
  EXPECT_NE(error_of([] { parse_crop("--crop", "a,2,3,4"); }).find("--crop"), std::string::npos);
  EXPECT_NE(error_of([] {
              check_crop("--crop", {8, 0, 4, 4}, 10, 10);
            }).find("not inside the 10x10"),
            std::string::npos);
  EXPECT_NE(error_of([] { check_crop("--crop", {0, 0, 0, 4}, 10, 10); }).find("at least 1"), std::string::npos);
  EXPECT_NO_THROW(check_crop("--crop", {6, 6, 4, 4}, 10, 10));
  Image img(4, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) img.set(x, y, Vec3(static_cast<float>(10 * y + x)));
  const Image cr = crop(img, {1, 1, 2, 2});
  EXPECT_EQ(cr.width, 2);
  EXPECT_EQ(cr.at(0, 0).x, 11.f);
  EXPECT_EQ(cr.at(1, 1).x, 22.f);
}

TEST(ImageFiles, PfmRoundTripIsBitExactAndBadFilesAreErrors) {
  const fs::path dir = test::temp_dir("pfm");
  const Image img = test_pattern(7, 5);
  write_image(img, (dir / "a.pfm").string());
  const Image back = read_image((dir / "a.pfm").string());
  ASSERT_EQ(back.width, 7);
  ASSERT_EQ(back.height, 5);
  EXPECT_EQ(std::memcmp(back.rgb.data(), img.rgb.data(), img.rgb.size() * sizeof(float)), 0);

  EXPECT_NE(error_of([&] { read_image((dir / "missing.pfm").string()); }).find("no such image file"),
            std::string::npos);
  test::write_file(dir / "trunc.pfm", "PF\n4 4\n-1.0\n0123");
  EXPECT_NE(error_of([&] { read_image((dir / "trunc.pfm").string()); }).find("truncated"), std::string::npos);
  test::write_file(dir / "bad.pfm", "P6\n4 4\n255\n");
  EXPECT_NE(error_of([&] { read_image((dir / "bad.pfm").string()); }).find("not a PFM"), std::string::npos);
  EXPECT_NE(error_of([&] { write_image(img, (dir / "a.tiff").string()); }).find("unknown image extension"),
            std::string::npos);
  EXPECT_NE(error_of([&] { check_output_image_path("--out", "x.jpg"); }).find("--out"), std::string::npos);
}

TEST(ImageFiles, ExrRoundTripIsBitExactAndPngIsWritten) {
  const fs::path dir = test::temp_dir("exr");
  const Image img = test_pattern(9, 6);
  if (!image_io_available()) {
    EXPECT_NE(error_of([&] { write_image(img, (dir / "a.exr").string()); }).find("RAYCOH_IMAGE_IO"), std::string::npos);
    GTEST_SKIP() << "built without image I/O";
  }
  write_image(img, (dir / "a.exr").string());
  const Image back = read_image((dir / "a.exr").string());
  ASSERT_EQ(back.width, 9);
  ASSERT_EQ(back.height, 6);
  EXPECT_EQ(std::memcmp(back.rgb.data(), img.rgb.data(), img.rgb.size() * sizeof(float)), 0);
  write_image(img, (dir / "a.png").string());
  EXPECT_GT(fs::file_size(dir / "a.png"), 50u);
  for (const auto& e : fs::directory_iterator(dir))  // no temporary file is left behind
    EXPECT_NE(e.path().filename().string()[0], '.') << e.path();
  test::write_file(dir / "broken.exr", "not an exr");
  EXPECT_THROW(read_image((dir / "broken.exr").string()), Error);
}
// read_image reads an EXR a strip of rows at a time (oiio/image_codec.cpp): images of several strips (the last one
// partial) and a tiled file with an offset data window read back exactly; a header claiming more than the file can
// be read fails with a one-line error.
TEST(ImageFiles, ExrReadsByStripsAndTiles) {
  if (!image_io_available()) GTEST_SKIP() << "built without image I/O";
  const fs::path dir = test::temp_dir("exr-strips");
  const Image img = test_pattern(2100, 1000);  // 499 rows a strip: 3 strips
  write_image(img, (dir / "big.exr").string());
  const Image back = read_image((dir / "big.exr").string());
  ASSERT_EQ(back.width, 2100);
  ASSERT_EQ(back.height, 1000);
  EXPECT_EQ(std::memcmp(back.rgb.data(), img.rgb.data(), img.rgb.size() * sizeof(float)), 0);
  const Image tiled = read_image((fs::path(RAYCOH_SOURCE_DIR) / "tests" / "data" / "tiled-70x40.exr").string());
  ASSERT_EQ(tiled.width, 70);
  ASSERT_EQ(tiled.height, 40);
  for (int y = 0; y < 40; y += 13)
    for (int x = 0; x < 70; x += 23) {
      const size_t p = 3 * (static_cast<size_t>(y) * 70 + x);
      EXPECT_EQ(tiled.rgb[p], x);
      EXPECT_EQ(tiled.rgb[p + 1], y);
      EXPECT_EQ(tiled.rgb[p + 2], x + 100.0f * y) << x << "," << y;
    }
  std::ifstream in(dir / "big.exr", std::ios::binary);
  std::string truncated((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  truncated.resize(truncated.size() / 2);
  test::write_file(dir / "half.exr", truncated);
  const std::string error = error_of([&] { read_image((dir / "half.exr").string()); });
  EXPECT_NE(error.find("half.exr"), std::string::npos) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
}
}  // namespace
}  // namespace raycoh
