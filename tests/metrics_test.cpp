// Error metrics (shading/metrics.h): exact values on hand-made images, bad input, non-finite pixels, and SSIM
// against scikit-image.
#include "shading/metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/error.h"
#include "tests/shading_test_util.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

using test::error_of;
using test::filled;
using test::test_pattern;

TEST(Metrics, ExactValuesOnHandMadeImages) {
  // 2x2, reference black, one test pixel white: linear squared errors 1 in 3 of 12 channel values.
  const Image ref = filled(2, 2, Vec3(0.f));
  Image test = ref;
  test.set(1, 0, Vec3(1.f));
  const ToneMap clamp{ToneMapKind::Clamp, 1.f};  // maps 0 -> 0 and 1 -> 1 exactly
  EXPECT_DOUBLE_EQ(mse(test, ref), 0.25);
  EXPECT_DOUBLE_EQ(rmse(test, ref), 0.5);
  EXPECT_NEAR(rel_mse(test, ref), 3.0 * (1.0 / 0.01) / 12.0, 1e-12);
  EXPECT_NEAR(psnr(test, ref, clamp), 10.0 * std::log10(1.0 / 0.25), 1e-12);  // 6.0206 dB
  EXPECT_TRUE(std::isinf(psnr(ref, ref, clamp)));
  EXPECT_DOUBLE_EQ(mse(ref, ref), 0.0);

  // relMSE is relative: the same relative error on a bright and a dim image gives about the same value.
  const Image dim = filled(3, 3, Vec3(1.f)), bright = filled(3, 3, Vec3(100.f));
  const double r1 = rel_mse(filled(3, 3, Vec3(1.1f)), dim), r2 = rel_mse(filled(3, 3, Vec3(110.f)), bright);
  EXPECT_NEAR(r1, 0.01 / 1.01, 1e-6);
  EXPECT_NEAR(r2, 0.01, 1e-5);
}

TEST(Metrics, SizeMismatchAndEmptyImagesAreErrors) {
  const Image a = filled(16, 12, Vec3(0.5f)), b = filled(12, 16, Vec3(0.5f));
  const std::string msg = error_of([&] { mse(a, b); });
  EXPECT_NE(msg.find("16x12"), std::string::npos) << msg;
  EXPECT_NE(msg.find("12x16"), std::string::npos) << msg;
  EXPECT_THROW(rmse(a, b), Error);
  EXPECT_THROW(rel_mse(a, b), Error);
  EXPECT_THROW(psnr(a, b), Error);
  EXPECT_THROW(ssim(a, b), Error);
  EXPECT_THROW(compare_images(a, b), Error);
  EXPECT_THROW(mse(Image(), Image()), Error);
  EXPECT_NE(error_of([] { ssim(filled(10, 30, Vec3(0.f)), filled(10, 30, Vec3(0.f))); }).find("11x11"),
            std::string::npos);
  EXPECT_TRUE(std::isnan(compare_images(filled(4, 4, Vec3(0.f)), filled(4, 4, Vec3(0.f))).ssim));
}

TEST(Metrics, NonFinitePixelsAreCountedAndLeftOut) {
  const Image ref = filled(12, 12, Vec3(0.25f));
  Image test = ref;
  test.set(3, 3, {NAN, 0.25f, 0.25f});
  test.set(4, 4, {INFINITY, 0.25f, 0.25f});
  const NonFiniteCount n = count_non_finite(test);
  EXPECT_EQ(n.nan_pixels, 1u);
  EXPECT_EQ(n.inf_pixels, 1u);
  const ErrorMetrics m = compare_images(test, ref);
  EXPECT_EQ(m.nan_pixels, 1u);
  EXPECT_EQ(m.inf_pixels, 1u);
  EXPECT_EQ(m.pixels_compared, 142u);
  EXPECT_EQ(m.mse, 0.0);
  EXPECT_TRUE(std::isfinite(m.ssim));
}

std::vector<double> gray(int w, int h, double (*f)(int, int)) {
  std::vector<double> v(static_cast<size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) v[static_cast<size_t>(y) * w + x] = f(x, y);
  return v;
}

// Reference values computed independently with scikit-image:
//   /usr/bin/python3 (Debian 12: numpy 1.24.2, scipy 1.10.1, python3-skimage 0.19.3)
//   skimage.metrics.structural_similarity(a, b, gaussian_weights=True, sigma=1.5, use_sample_covariance=False,
//                                         data_range=1.0)
// on float64 arrays of shape (h, w) with a[y][x], b[y][x] given by the same formulas as below.
TEST(Metrics, SsimMatchesScikitImage) {
  struct Case {
    int w, h;
    double (*a)(int, int);
    double (*b)(int, int);
    double expected;
  };
  const Case cases[] = {
      {16, 16, [](int x, int y) { return ((x * 7 + y * 13) % 17) / 16.0; },
       [](int x, int y) {
         return std::min(1.0, std::max(0.0, ((x * 7 + y * 13) % 17) / 16.0 + (((x * x + 3 * y) % 5) - 2) / 20.0));
       },
       0.9742238449621069},
      {23, 19, [](int x, int y) { return (x + y) / 40.0; },
       [](int x, int y) { return (x + y) / 40.0 * 0.8 + 0.1 * ((x * y) % 3) / 2.0; }, 0.7441923147281507},
      {32, 24, [](int x, int y) { return ((x / 4 + y / 4) % 2) * 0.9 + 0.05; }, [](int, int) { return 0.5; },
       0.004576300354071375},
      {11, 11, [](int x, int y) { return ((x * 3 + y * 5) % 11) / 10.0; },
       [](int x, int y) { return ((x * 5 + y * 3) % 11) / 10.0; }, -0.10923742690708699},
  };
  for (const Case& c : cases) {
    const double s = ssim_gray(gray(c.w, c.h, c.a), gray(c.w, c.h, c.b), c.w, c.h);
    EXPECT_NEAR(s, c.expected, 1e-12) << c.w << "x" << c.h;
  }
}

TEST(Metrics, SsimOfIdenticalImagesIsOneAndDropsWithNoise) {
  const Image a = test_pattern(40, 30);
  EXPECT_DOUBLE_EQ(ssim(a, a), 1.0);
  Image b = a;
  for (size_t i = 0; i < b.rgb.size(); ++i) b.rgb[i] += 0.05f * static_cast<float>((i * 7919) % 13) / 13.f;
  const double s = ssim(b, a);
  EXPECT_LT(s, 1.0);
  EXPECT_GT(s, 0.0);
}
}  // namespace
}  // namespace raycoh
