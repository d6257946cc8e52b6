// The typed record of what a key encoder computes (a plain struct, free of the plugin machinery so that
// cuda/device_keys.cu can include it under nvcc): kind (encoders/key_code.h), width, box and the few numbers the
// key functions take. Each encoder fills it from the values it read from its parameter table (Encoder::recipe());
// the GPU builds the same keys from it, never from the parameter text.
#pragma once

#include "core/vec.h"
#include "encoders/key_code.h"

namespace raycoh {

struct KeyRecipe {
  KeyKind kind = KeyKind::None;
  int bits = 0;               // key width: 32 | 64 (0 for none)
  Bounds box;                 // the scene bounds positions are quantised in
  float length_factor = 0.f;  // twopoint, mlhcc: L
  float lambda = 0.f;         // mlhcc
  bool with_end = true;       // mlhcc: points=both
  bool global_ranks = false;  // mlhcc: ranks=global
};

// The key function's arguments of a recipe; mlhcc's cut table is the caller's (host or device pointers).
inline KeyArgs key_args(const KeyRecipe& recipe, const MlhccCuts& cuts = {}) {
  KeyArgs a;
  a.bits = recipe.bits;
  a.box = recipe.box;
  a.length_factor = recipe.length_factor;
  a.with_end = recipe.with_end;
  a.cuts = cuts;
  return a;
}

}  // namespace raycoh
