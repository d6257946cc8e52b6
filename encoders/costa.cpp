// Costa: direction first, then origin (Costa et al. 2015, "Accelerating Occlusion Rendering on a GPU via Ray
// Classification", as compared by Meister et al. 2020). The code is the spherical direction's phi and theta,
// 4 bits each, interleaved phi first, then the origin's 3-D Morton code with 15 bits per axis; the 11 low bits
// are zero. A 32-bit key holds the 8 direction bits and 8/8/8 origin bits: rays are first binned into 256
// direction cells, then ordered by origin inside each.
//
// Parameters: costa_params() below (the shared key_bits_param()).
// Recorded with them: box=lo..hi, the scene bounds positions are quantised in.
#include "encoders/key_encoder.h"

namespace raycoh {

const ParamTable& costa_params() {
  static const ParamTable table = {key_bits_param()};
  return table;
}

std::unique_ptr<Encoder> make_costa_encoder(ParamSet& params, const EncoderContext& context) {
  const int bits = read_key_bits(params);
  const Bounds box = context.bounds;
  return make_recipe_encoder("costa", KeyRecipe{KeyKind::Costa, bits, box}, finish_encoder_params(params, box));
}

}  // namespace raycoh
