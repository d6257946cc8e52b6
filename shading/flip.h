// ꟻLIP (Andersson et al. 2020) through NVIDIA's reference implementation (PyPI flip-evaluator, installed by
// scripts/setup into .venv), run as an external program: the one adapter of `raycoh quality`'s flip columns.
#pragma once

#include <cmath>
#include <string>
#include <vector>

namespace raycoh {

// s single-quoted for the shell (the commands of flip.cpp and denoise.cpp go through popen).
std::string shell_quoted(const std::string& s);

// $RAYCOH_FLIP, else .venv/bin/flip in the working folder; "" when neither exists.
std::string flip_program();

// Mean LDR-FLIP of two display images (the PNGs written); NaN when flip fails or prints no mean.
double run_flip(const std::string& program, const std::string& ref, const std::string& test);

// HDR-FLIP (flip's mode for EXR input) of linear renders against a linear reference, in one call of the flip
// program with its defaults: ACES tone mapper, 67 pixels per degree, and the exposure range (start, stop, count)
// that flip derives from the reference's luminance, which `exposure` reports as "start..stop/count".
struct HdrFlip {
  double mean = std::nan("");    // mean over the test images of each image's mean HDR-FLIP
  std::vector<double> per_test;  // each test image's mean HDR-FLIP, in the order given (empty when flip failed)
  std::string exposure;
};
HdrFlip run_hdr_flip(const std::string& program, const std::string& ref, const std::vector<std::string>& tests,
                     const std::string& dir);

}  // namespace raycoh
