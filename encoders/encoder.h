// Ray-reordering encoders: RayBatch -> keys -> stable radix sort -> permutation (DESIGN.md section 3).
// The foundation ships only `none` (rays are traced in the generator's order); the reordering baselines
// (origin, reis, costa, aila, twopoint, mlhcc) plug in here.
#pragma once

#include <string>
#include <vector>

namespace raycoh {

struct EncoderInfo {
  std::string name;
  std::string summary;
  std::string params;
};

const std::vector<EncoderInfo>& encoder_infos();

}  // namespace raycoh
