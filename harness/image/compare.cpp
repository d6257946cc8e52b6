#include "harness/image/compare.h"

// `raycoh compare TEST REFERENCE`: every metric of shading/metrics.h for two image files.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>

#include "harness/common/command.h"
#include "harness/image/render_common.h"
#include "shading/metrics.h"

namespace raycoh {

int run_compare(const CompareOptions& o) {
  check_exposure(o.tone_map);
  const Image test = read_image_for("test image", o.test);
  const Image ref = read_image_for("reference image", o.reference);
  check_same_size(test, ref);
  const ToneMap tm = resolved(o.tone_map, ref);
  const ErrorMetrics m = compare_images(test, ref, tm);
  std::printf("test %s vs reference %s (%dx%d)\n", o.test.c_str(), o.reference.c_str(), ref.width, ref.height);
  std::printf("rmse %.6g\nrel_mse %.6g (eps %.2g)\nmse %.6g\npsnr %.4f dB (tone map %s, peak %.1f)\n", m.rmse,
              m.rel_mse, kRelMseEpsilon, m.mse, m.psnr, describe(tm).c_str(), kPsnrPeak);
  std::printf("ssim %.6f%s\n", m.ssim, std::isnan(m.ssim) ? " (images smaller than the 11x11 SSIM window)" : "");
  std::printf("nan_pixels %llu\ninf_pixels %llu\n", static_cast<unsigned long long>(m.nan_pixels),
              static_cast<unsigned long long>(m.inf_pixels));
  return 0;
}

BoundCommand bind_compare(CLI::App& parent) {
  auto o = std::make_shared<CompareOptions>();
  CLI::App* cmd = parent.add_subcommand("compare", "every error metric between two image files");
  cmd->add_option("test", o->test, "image to measure (.exr or .pfm)")->required();
  cmd->add_option("reference", o->reference, "reference image (.exr or .pfm)")->required();
  return {cmd, [o](const Provenance&) { return run_compare(*o); }};
}

}  // namespace raycoh
