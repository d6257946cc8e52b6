// Issue 12 items 1 and 3 (shading/metrics.h, harness/image/quality.h): the measurement protocols, linear metrics, the
// reference's own noise from two half-references, the error of downsampled images, and the per-pixel bias test.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <set>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "generators/generator.h"
#include "harness/image/quality.h"
#include "plugins/tracer_registry.h"
#include "shading/metrics.h"
#include "shading/reference.h"
#include "tests/shading_test_util.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

namespace fs = std::filesystem;

// A smooth "truth" image with values in [0.2, 1.2].
Image truth(int w, int h) {
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      img.set(x, y, Vec3(0.2f + static_cast<float>(x) / w, 0.5f, 0.2f + static_cast<float>(y) / h));
  return img;
}

// truth + noise of standard deviation sigma, the same noise value over each block x block square (block 1: white).
Image noisy(const Image& t, float sigma, int block, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> n(0.f, sigma);
  Image out = t;
  std::vector<Vec3> blocks(static_cast<size_t>((t.width / block + 1) * (t.height / block + 1)));
  for (Vec3& b : blocks) b = Vec3(n(rng), n(rng), n(rng));
  for (int y = 0; y < t.height; ++y)
    for (int x = 0; x < t.width; ++x) {
      const Vec3 e = blocks[static_cast<size_t>(y / block) * (t.width / block + 1) + x / block];
      const Vec3 v = t.at(x, y);
      out.set(x, y, Vec3(v.x + e.x, v.y + e.y, v.z + e.z));
    }
  return out;
}

TEST(ImageError, DownsampledErrorSeparatesWhiteFromBlockNoise) {
  const Image t = truth(128, 96);
  const Image white = noisy(t, 0.05f, 1, 1), blocks = noisy(t, 0.05f, 8, 2);
  const double w1 = rel_mse(white, t), b1 = rel_mse(blocks, t);
  ASSERT_GT(w1, 0);
  ASSERT_GT(b1, 0);
  // White noise: each 2x step divides the error by ~4. Block-correlated noise (8x8 blocks): it stays.
  for (int k : {2, 4, 8}) {
    const double w = rel_mse(box_downsample(white, k), box_downsample(t, k)) / w1;
    const double b = rel_mse(box_downsample(blocks, k), box_downsample(t, k)) / b1;
    EXPECT_NEAR(w * k * k, 1.0, 0.35) << k;
    EXPECT_GT(b, 0.6) << k;
  }
  // Box downsampling is the block mean; the image is cropped to whole blocks.
  const Image d = box_downsample(truth(10, 7), 3);
  EXPECT_EQ(d.width, 3);
  EXPECT_EQ(d.height, 2);
  EXPECT_NEAR(d.at(0, 0).x, 0.2 + 1.0 / 10, 1e-6);
  EXPECT_NE(test::error_of([&] { box_downsample(t, 0); }).find("box downsample by 0"), std::string::npos);
}

TEST(ImageError, HalfReferenceNoiseMatchesTheKnownNoise) {
  const Image t = truth(160, 120);
  const float s = 0.04f;  // noise of each half
  const Image a = noisy(t, s, 1, 11), b = noisy(t, s, 1, 12);
  Image full = a;
  for (size_t i = 0; i < full.rgb.size(); ++i) full.rgb[i] = 0.5f * (a.rgb[i] + b.rgb[i]);
  const ReferenceNoise n = reference_noise(full, a);
  const double expected = s * s / 2;  // the variance of the mean of the halves
  EXPECT_NEAR(n.mse / expected, 1.0, 0.03);
  EXPECT_NEAR(n.mse / mse(full, t), 1.0, 0.03);  // the noise the full reference really has
  EXPECT_NEAR(n.rel_mse / rel_mse(full, t), 1.0, 0.03);
  // In linear space the PSNR's MSE is the linear MSE.
  EXPECT_NEAR(reference_noise(full, a, {}, MetricSpace::Linear).metric_mse / n.mse, 1.0, 1e-6);
  // A test image against the noisy reference: its error against the truth comes back once the noise is taken out.
  const Image x = noisy(t, 0.03f, 1, 13);
  EXPECT_NEAR(minus_noise(mse(x, full), n.mse) / mse(x, t), 1.0, 0.05);
  EXPECT_EQ(minus_noise(0.1, 0.2), 0.0);
  EXPECT_TRUE(std::isnan(minus_noise(std::nan(""), 0.2)));  // undefined stays undefined, not 0
}

// The noise estimate's standard error (what is left of the reference's noise in a corrected figure) is the spread
// the estimate really has: 24 independent pairs of halves, small images so that the spread is visible.
TEST(ImageError, ReferenceNoiseStandardErrorIsTheEstimatesSpread) {
  const Image t = truth(24, 16);
  const float s = 0.04f;
  std::vector<double> est;
  double se = 0;
  for (uint32_t k = 0; k < 24; ++k) {
    const Image a = noisy(t, s, 1, 100 + 2 * k), b = noisy(t, s, 1, 101 + 2 * k);
    Image full = a;
    for (size_t i = 0; i < full.rgb.size(); ++i) full.rgb[i] = 0.5f * (a.rgb[i] + b.rgb[i]);
    const ReferenceNoise n = reference_noise(full, a);
    est.push_back(n.mse);
    se += n.mse_se / 24;
    EXPECT_GT(n.rel_mse_se, 0);
    EXPECT_GT(n.metric_mse_se, 0);
  }
  double mean = 0, var = 0;
  for (double e : est) mean += e / est.size();
  for (double e : est) var += (e - mean) * (e - mean) / (est.size() - 1);
  EXPECT_NEAR(se / std::sqrt(var), 1.0, 0.35);  // the spread of 24 estimates is itself known to ~15%
  // The residual share: standard error over the figure.
  ReferenceNoise n;
  n.mse = 0.01, n.mse_se = 0.001;
  EXPECT_DOUBLE_EQ(correct_for_noise(n, 0.1, 0, 0).residual_share, 0.01);
}

TEST(ImageError, LinearMetricsUseTheLinearMseAndPeakOne) {
  const Image t = truth(16, 16), x = noisy(t, 0.1f, 1, 3);
  EXPECT_NEAR(psnr(x, t, {}, MetricSpace::Linear), -10 * std::log10(mse(x, t)), 1e-9);
  EXPECT_NE(psnr(x, t, {}, MetricSpace::Linear), psnr(x, t));
  EXPECT_LT(ssim(x, t, {}, MetricSpace::Linear), 1.0);
  EXPECT_EQ(parse_metric_space("--metrics", "linear"), MetricSpace::Linear);
  EXPECT_EQ(parse_metric_space("--metrics", "tonemapped"), MetricSpace::ToneMapped);
  EXPECT_NE(test::error_of([] { parse_metric_space("--metrics", "log"); }).find("--metrics 'log'"), std::string::npos);
}

TEST(ImageError, ProtocolSetsValuesAndExplicitOptionsOverride) {
  RenderCommon c;
  int frames = 32, ref_frames = 512;
  std::set<std::string> given;
  const auto is_given = [&](const std::string& o) { return given.count(o) > 0; };
  apply_protocol(protocol_named("--protocol", "paper"), is_given, c, &frames, "--frames", &ref_frames, "--ref-frames");
  EXPECT_EQ(c.protocol, "paper");
  EXPECT_EQ(c.width, 1920);
  EXPECT_EQ(c.height, 1080);
  EXPECT_EQ(frames, 128);
  EXPECT_EQ(ref_frames, 4096);
  EXPECT_EQ(c.metrics, MetricSpace::Linear);

  RenderCommon d;
  d.width = 480;
  d.height = 270;
  frames = 8;
  ref_frames = 512;
  given = {"--res", "--frames", "--metrics"};
  apply_protocol(protocol_named("--protocol", "paper"), is_given, d, &frames, "--frames", &ref_frames, "--ref-frames");
  EXPECT_EQ(d.width, 480);
  EXPECT_EQ(d.height, 270);
  EXPECT_EQ(frames, 8);
  EXPECT_EQ(ref_frames, 4096);
  EXPECT_EQ(d.metrics, MetricSpace::ToneMapped);

  const Protocol ci = protocol_named("--protocol", "ci");
  const RenderCommon defaults;
  const QualityOptions q;
  EXPECT_EQ(ci.width, defaults.width);  // ci is the defaults
  EXPECT_EQ(ci.height, defaults.height);
  EXPECT_EQ(ci.frames, q.frames);
  EXPECT_EQ(ci.ref_frames, q.ref_frames);
  EXPECT_EQ(ci.metrics, defaults.metrics);
  EXPECT_NE(test::error_of([] { protocol_named("--protocol", "fast"); }).find("--protocol 'fast'"), std::string::npos);
}

// The statistical test: NoOpt (unbiased) on cornell at 32x24, 96 frames against a 256-frame reference with
// independent seeds. At a 5% false-alarm rate per pixel, ~5% of pixels exclude zero; the whole-image test has a 5%
// false-alarm rate, and with this fixed seed it passes. A reference 20% too dark is found biased.
TEST(ImageError, BiasMapOfAnUnbiasedGeneratorIsConsistentWithZero) {
  const Scene s = load_scene("cornell");
  const Bvh bvh = build_bvh(s);
  ReferenceRequest req;
  req.scene_spec = "cornell";
  req.settings = test::small(32, 24, 1001);
  req.frames = 256;
  req.revision = "test-bias";
  req.cache_dir = test::temp_dir("biasref").string();
  const Reference ref = get_reference(s, bvh, req);
  ASSERT_FALSE(ref.first_half.empty());

  auto tracer = make_tracer({"cpu", ""}, s, bvh);
  auto gen = make_generator({"noopt", ""});
  PathTracer pt(s, *tracer, *gen, test::small(32, 24, 1));
  BiasSamples samples(32, 24);
  for (uint32_t f = 0; f < 96; ++f) {
    Accumulator frame(32, 24);
    pt.render_frame(f, frame);
    samples.add_frame(frame);
  }
  const BiasReport r = bias_test(samples, ref.image, &ref.first_half);
  EXPECT_TRUE(r.consistent) << r.mean_bias << " +- " << r.mean_bias_ci;
  EXPECT_GT(r.excluded_fraction, 0.01);
  EXPECT_LT(r.excluded_fraction, 0.10);
  // Fireflies raise a pixel's difference and its spread together, so z^2 averages somewhat below 1.
  EXPECT_GT(r.z2, 0.5);
  EXPECT_LT(r.z2, 1.3);
  EXPECT_EQ(r.map.width, 32);

  Image darker = ref.image, darker_half = ref.first_half;
  for (float& v : darker.rgb) v *= 0.8f;
  for (float& v : darker_half.rgb) v *= 0.8f;
  const BiasReport b = bias_test(samples, darker, &darker_half);
  EXPECT_FALSE(b.consistent);
  EXPECT_GT(b.mean_bias, 0);
  EXPECT_GT(b.excluded_fraction, r.excluded_fraction);
  EXPECT_NE(test::error_of([&] { bias_test(BiasSamples(32, 24), ref.image, nullptr); }).find("at least 2 frames"),
            std::string::npos);
}

// The share of an error figure that is the reference's noise, and the figures without it (quality's and converge's
// columns, one definition).
TEST(ImageError, NoiseCorrectionTakesTheReferenceNoiseOut) {
  ReferenceNoise n;
  n.mse = 0.01;
  n.rel_mse = 0.02;
  n.metric_mse = 0.001;
  const NoiseCorrected c = correct_for_noise(n, 0.1, 0.1, 0.01);
  EXPECT_DOUBLE_EQ(c.share, 0.2);  // the largest of 0.1, 0.2, 0.1
  EXPECT_DOUBLE_EQ(c.mse, 0.09);
  EXPECT_DOUBLE_EQ(c.rel_mse, 0.08);
  EXPECT_NEAR(c.psnr, 10 * std::log10(1 / 0.009), 1e-12);
  EXPECT_EQ(correct_for_noise(n, 0.005, 0.1, 0.01).mse, 0.0);  // never below 0
  EXPECT_EQ(correct_for_noise(ReferenceNoise{}, 0, 0, 0).share, 0.0);
}

// Synthetic pixels with a known mean (the reference, without noise), n = 128 frames, fixed seed: the calibration of
// the per-pixel band. Normal samples: both shares at the nominal 5%. Skewed samples (lognormal, sigma 1; and rare
// bright events, which is what a path-traced pixel's samples look like): the plain t band excludes zero too often
// (its false-alarm rate is not 5%), Hall's skewness-corrected statistic (excluded_skew) comes back near 5%. A bias
// of a third of a standard error per sample is found by both.
// With `blocks`, the test of the 4 x 4 box-downsampled frames against the downsampled reference (quality's
// bias_excluded_ds4).
BiasReport synthetic_bias(const char* kind, double shift, uint32_t seed, bool blocks = false) {
  constexpr int kW = 200, kH = 100, kFrames = 128;
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const size_t P = static_cast<size_t>(kW) * kH;
  std::vector<double> p_event(P), mean(P);
  for (size_t p = 0; p < P; ++p) p_event[p] = 0.05 + 0.45 * uniform(rng);
  const std::string k = kind;
  for (size_t p = 0; p < P; ++p) mean[p] = k == "normal" ? 1.0 : k == "lognormal" ? std::exp(0.5) : 1.0;
  BiasSamples s(kW, kH), s4(kW / 4, kH / 4);
  std::vector<double> luma(P);
  for (int f = 0; f < kFrames; ++f) {
    for (size_t p = 0; p < P; ++p) {
      double y;
      if (k == "normal")
        y = 1.0 + 0.5 * normal(rng);
      else if (k == "lognormal")
        y = std::exp(normal(rng));
      else  // rare events: a bright sample of mean 1 / p with probability p, else 0
        y = uniform(rng) < p_event[p] ? -std::log(1 - uniform(rng)) / p_event[p] : 0.0;
      luma[p] = y + shift;
    }
    s.add_luma(luma);
    s4.add_luma(box_downsample_luma(luma, kW, kH, 4));
  }
  Image ref(kW, kH);
  for (size_t p = 0; p < P; ++p) {
    const float m = static_cast<float>(mean[p]);
    ref.set(p, Vec3(m, m, m));
  }
  return blocks ? bias_test(s4, box_downsample(ref, 4), nullptr) : bias_test(s, ref, nullptr);
}

TEST(ImageError, SkewCorrectedBiasShareIsCalibratedOnSyntheticPixels) {
  const BiasReport normal = synthetic_bias("normal", 0.0, 7);
  EXPECT_NEAR(normal.excluded_fraction, 0.05, 0.006);
  EXPECT_NEAR(normal.excluded_skew, 0.05, 0.006);
  EXPECT_NEAR(normal.excluded_dark, 0.025, 0.005);
  EXPECT_NEAR(normal.excluded_bright, 0.025, 0.005);
  EXPECT_DOUBLE_EQ(normal.excluded_dark + normal.excluded_bright, normal.excluded_fraction);
  const BiasReport lognormal = synthetic_bias("lognormal", 0.0, 8);
  EXPECT_GT(lognormal.excluded_dark, 3 * lognormal.excluded_bright);  // skewness: the excess is dark
  EXPECT_GT(lognormal.excluded_fraction, 0.068);                      // the plain t band: ~7.7%
  EXPECT_LT(lognormal.excluded_skew, 0.066);                          // corrected: ~6.2% (heavy tail left)
  EXPECT_GT(lognormal.excluded_skew, 0.045);
  const BiasReport rare = synthetic_bias("rare", 0.0, 9);
  EXPECT_GT(rare.excluded_fraction, 0.07);
  EXPECT_NEAR(rare.excluded_skew, 0.05, 0.012);
  EXPECT_TRUE(normal.consistent && lognormal.consistent && rare.consistent);
  // 4 x 4 blocks: 16 x the samples per mean, a quarter of the skewness, near 5% for both skewed kinds (1250 blocks).
  EXPECT_NEAR(synthetic_bias("lognormal", 0.0, 8, true).excluded_fraction, 0.05, 0.015);
  EXPECT_NEAR(synthetic_bias("rare", 0.0, 9, true).excluded_fraction, 0.05, 0.015);
  EXPECT_GT(synthetic_bias("normal", 0.17, 7, true).excluded_fraction, 0.99);
  // A bias of 0.17 (a third of the normal samples' sigma / sqrt(1), ~3.8 standard errors of a 128-sample mean).
  const BiasReport biased = synthetic_bias("normal", 0.17, 7);
  EXPECT_GT(biased.excluded_fraction, 0.5);
  EXPECT_GT(biased.excluded_skew, 0.5);
  EXPECT_GT(biased.excluded_bright, 0.5);
  EXPECT_LT(biased.excluded_dark, 0.001);
  EXPECT_FALSE(biased.consistent);
}

}  // namespace
}  // namespace raycoh
