// TwoPoint: origin and estimated end point (Meister et al. 2020, "On Ray Reordering Techniques for Faster GPU Ray
// Tracing", the fixed-length termination estimate the paper we reproduce uses). The end point is b = o + L d with
// L = min(L_factor x the longest extent of the scene box, the ray's tmax, the distance to where the ray leaves the
// scene box), never negative; origin a and b are quantised with 13 bits per axis and interleaved as a 6-D Morton
// code (ax ay az bx by bz per level), keeping the top 64 of its 78 bits. A 32-bit key holds a 6/6/5 and b 5/5/5.
// Rays that start and (probably) end near each other cross the same part of the tree.
//
// Parameters: twopoint_params() below (the shared key_bits_param() and end_point_param(); L = 0: b = a).
// Recorded with them: box=lo..hi, the scene bounds positions are quantised in and the end point is clamped to.
#include "encoders/key_encoder.h"

namespace raycoh {

const ParamTable& twopoint_params() {
  static const ParamTable table = {key_bits_param(), end_point_param()};
  return table;
}

std::unique_ptr<Encoder> make_twopoint_encoder(ParamSet& params, const EncoderContext& context) {
  const int bits = read_key_bits(params);
  const float length = params.get_float("L");
  const Bounds box = context.bounds;
  return make_recipe_encoder("twopoint", KeyRecipe{KeyKind::TwoPoint, bits, box, length},
                             finish_encoder_params(params, box));
}

}  // namespace raycoh
