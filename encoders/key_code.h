// One key function per KeyRecipe kind (encoders/key_recipe.h), shared by the CPU key encoders
// (make_recipe_encoder, encoders/key_encoder.h) and the CUDA key kernel (cuda/device_keys.cu): the recipe's numbers
// in a plain struct, and the code function of encoders/keys.h each kind runs. Host and device code (RAYCOH_HD).
// A new GPU-capable key is a KeyKind, its code function in keys.h and its line here.
#pragma once

#include <cstdint>
#include <type_traits>

#include "core/platform.h"
#include "core/ray.h"
#include "encoders/key_recipe.h"
#include "encoders/keys.h"

namespace raycoh {

struct KeyArgs {
  int bits = 0;
  Bounds box;
  float length_factor = 0.f;
  bool with_end = true;
  MlhccCuts cuts{};  // mlhcc: a view of its cut table (host or device pointers)
};

inline KeyArgs key_args(const KeyRecipe& recipe, const MlhccCuts& cuts = {}) {
  KeyArgs a;
  a.bits = recipe.bits;
  a.box = recipe.box;
  a.length_factor = recipe.length_factor;
  a.with_end = recipe.with_end;
  a.cuts = cuts;
  return a;
}

// The 64-bit code of one ray under kind Kind (the key is its top `bits` bits: key_from_code).
template <KeyKind Kind>
RAYCOH_HD RAYCOH_INLINE uint64_t key_code(const KeyArgs& a, const Ray& r) {
  if constexpr (Kind == KeyKind::Origin) return origin_code(r.org, a.box);
  if constexpr (Kind == KeyKind::Reis) return reis_code(r.org, r.dir, a.box);
  if constexpr (Kind == KeyKind::Costa) return costa_code(r.org, r.dir, a.box);
  if constexpr (Kind == KeyKind::Aila) return aila_code(r.org, r.dir, a.box);
  if constexpr (Kind == KeyKind::TwoPoint) return twopoint_code(r.org, r.dir, r.tmax, a.box, a.length_factor);
  if constexpr (Kind == KeyKind::Mlhcc)
    return mlhcc_code(r.org, r.dir, r.tmax, a.box, a.length_factor, a.cuts, a.with_end, a.bits);
  return 0;
}

// Calls f(std::integral_constant<KeyKind, K>{}) for the recipe's kind K (none for KeyKind::None); returns whether
// the kind has a key function.
template <class F>
bool with_key_kind(KeyKind kind, F&& f) {
  switch (kind) {
    case KeyKind::Origin:
      f(std::integral_constant<KeyKind, KeyKind::Origin>{});
      return true;
    case KeyKind::Reis:
      f(std::integral_constant<KeyKind, KeyKind::Reis>{});
      return true;
    case KeyKind::Costa:
      f(std::integral_constant<KeyKind, KeyKind::Costa>{});
      return true;
    case KeyKind::Aila:
      f(std::integral_constant<KeyKind, KeyKind::Aila>{});
      return true;
    case KeyKind::TwoPoint:
      f(std::integral_constant<KeyKind, KeyKind::TwoPoint>{});
      return true;
    case KeyKind::Mlhcc:
      f(std::integral_constant<KeyKind, KeyKind::Mlhcc>{});
      return true;
    case KeyKind::None:
      break;
  }
  return false;
}

}  // namespace raycoh
