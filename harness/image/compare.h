// `raycoh compare test.exr reference.exr` (compare.cpp): every metric of shading/metrics.h between two images.
#pragma once

#include <string>

#include "shading/image.h"

namespace raycoh {

// `raycoh compare test.exr reference.exr`: prints every metric of shading/metrics.h.
struct CompareOptions {
  std::string test, reference;
  ToneMap tone_map{ToneMapKind::Aces, 1.f, true};
};
int run_compare(const CompareOptions& options);

}  // namespace raycoh
