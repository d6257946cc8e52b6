// Reis: origin first, then direction (Reis et al. 2017, "Coherent Ray-Space Hierarchy via Ray Hashing and
// Sorting", as compared by Meister et al. 2020). The code is the top 22 bits of the origin's Morton code
// (encoders/origin.cpp: 8/7/7 bits of x/y/z), then the spherical direction's phi and theta, 21 bits each,
// interleaved phi first; a 32-bit key holds phi and theta with 5 bits each.
//
// Parameters: reis_params() below (the shared key_bits_param()).
// Recorded with them: box=lo..hi, the scene bounds positions are quantised in.
#include "encoders/key_encoder.h"

namespace raycoh {

const ParamTable& reis_params() {
  static const ParamTable table = {key_bits_param()};
  return table;
}

std::unique_ptr<Encoder> make_reis_encoder(ParamSet& params, const EncoderContext& context) {
  const int bits = read_key_bits(params);
  const Bounds box = context.bounds;
  return make_recipe_encoder("reis", KeyRecipe{KeyKind::Reis, bits, box}, finish_encoder_params(params, box));
}

}  // namespace raycoh
