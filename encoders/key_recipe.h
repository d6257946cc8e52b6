// The typed record of what a key encoder computes (a plain struct, free of the plugin machinery so that
// cuda/device_keys.cu can include it under nvcc): kind, width, box and the few numbers the code functions of
// encoders/keys.h take. Each encoder fills it from the values it read from its parameter table
// (Encoder::recipe()); the GPU builds the same keys from it, never from the parameter text.
#pragma once

#include "core/vec.h"

namespace raycoh {

enum class KeyKind { None, Origin, Reis, Costa, Aila, TwoPoint, Mlhcc };
struct KeyRecipe {
  KeyKind kind = KeyKind::None;
  int bits = 0;               // key width: 32 | 64 (0 for none)
  Bounds box;                 // the scene bounds positions are quantised in
  float length_factor = 0.f;  // twopoint, mlhcc: L
  float lambda = 0.f;         // mlhcc
  bool with_end = true;       // mlhcc: points=both
  bool global_ranks = false;  // mlhcc: ranks=global
};

}  // namespace raycoh
