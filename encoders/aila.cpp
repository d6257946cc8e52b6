// AilaCompact: origin and direction interleaved in 3-bit groups (the compact key of Aila & Karras 2010,
// "Architecture Considerations for Tracing Incoherent Rays", as compared by Meister et al. 2020). Origin and
// direction (d + 1) / 2 are quantised with 13 bits per axis; the code holds the origin's three top levels alone
// (o12 o11 o10, x y z each), then groups alternating an origin level and a direction level three levels higher
// (o9 d12 o8 d11 ... o0 d3), truncated to 64 bits. A 32-bit key holds origin 7/7/7 and direction 4/4/3 bits:
// the coarse origin decides first, then origin and direction refine together.
//
// Parameters: aila_params() below (the shared key_bits_param()).
// Recorded with them: box=lo..hi, the scene bounds positions are quantised in.
#include "encoders/key_encoder.h"

namespace raycoh {

const ParamTable& aila_params() {
  static const ParamTable table = {key_bits_param()};
  return table;
}

std::unique_ptr<Encoder> make_aila_encoder(ParamSet& params, const EncoderContext& context) {
  const int bits = read_key_bits(params);
  const Bounds box = context.bounds;
  return make_recipe_encoder("aila", KeyRecipe{KeyKind::Aila, bits, box}, finish_encoder_params(params, box));
}

}  // namespace raycoh
