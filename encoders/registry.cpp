// The explicit encoder registry.
#include "encoders/encoder.h"

namespace raycoh {

const std::vector<EncoderInfo>& encoder_infos() {
  static const std::vector<EncoderInfo> infos = {
      {"none", "no reordering: rays are traced in the order the generator wrote them", "(no parameters)"},
  };
  return infos;
}

}  // namespace raycoh
