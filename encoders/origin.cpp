// Origin: rays sorted by the 3-D Morton code of their origin, 21 bits per axis (x y z per level), left-aligned in
// 64 bits; a 32-bit key holds 11/11/10 bits of x/y/z. The simplest key of Meister et al. 2020 ("On Ray Reordering
// Techniques for Faster GPU Ray Tracing"): rays that start close together are traced together, whatever their
// direction.
//
// Parameters: origin_params() below (the shared key_bits_param()).
// Recorded with them: box=lo..hi, the scene bounds positions are quantised in.
#include "encoders/key_encoder.h"

namespace raycoh {

const ParamTable& origin_params() {
  static const ParamTable table = {key_bits_param()};
  return table;
}

std::unique_ptr<Encoder> make_origin_encoder(ParamSet& params, const EncoderContext& context) {
  const int bits = read_key_bits(params);
  const Bounds box = context.bounds;
  return make_recipe_encoder("origin", KeyRecipe{KeyKind::Origin, bits, box}, finish_encoder_params(params, box));
}

}  // namespace raycoh
