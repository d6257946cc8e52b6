// The key kinds that run on the CPU and the GPU alike, one line each (RAYCOH_KEY_KINDS), and their key functions:
// the KeyKind enum, the name of each kind, key_code<Kind> and with_key_kind all expand that one list, so a new
// GPU-capable key is its line here and, where the code is more than one call, its function in encoders/keys.h or
// here. The CPU key encoders run these functions through make_recipe_encoder (encoders/key_encoder.h), the CUDA key
// kernel (cuda/device_keys.cu) through the same key_code. Host and device code (RAYCOH_HD), free of the plugin
// machinery so nvcc can include it; the recipe that selects a kind is encoders/key_recipe.h.
#pragma once

#include <cstdint>
#include <string>
#include <type_traits>

#include "core/platform.h"
#include "core/ray.h"
#include "encoders/keys.h"

namespace raycoh {

// The numbers a key function reads (filled from a KeyRecipe by key_args, encoders/key_recipe.h).
struct KeyArgs {
  int bits = 0;
  Bounds box;
  float length_factor = 0.f;
  bool with_end = true;
  MlhccCuts cuts{};  // mlhcc: a view of its cut table (host or device pointers)
};

// X(Kind, "encoder name", the 64-bit code of ray `r` under the arguments `a`; the key is its top `bits` bits:
// key_from_code). The name is the registered encoder that makes this kind's recipe.
#define RAYCOH_KEY_KINDS(X)                                                            \
  X(Origin, "origin", origin_code(r.org, a.box))                                       \
  X(Reis, "reis", reis_code(r.org, r.dir, a.box))                                      \
  X(Costa, "costa", costa_code(r.org, r.dir, a.box))                                   \
  X(Aila, "aila", aila_code(r.org, r.dir, a.box))                                      \
  X(TwoPoint, "twopoint", twopoint_code(r.org, r.dir, r.tmax, a.box, a.length_factor)) \
  X(Mlhcc, "mlhcc", mlhcc_code(r.org, r.dir, r.tmax, a.box, a.length_factor, a.cuts, a.with_end, a.bits))

#define RAYCOH_KEY_KIND_ENUM(kind, name, code) kind,
enum class KeyKind { None, RAYCOH_KEY_KINDS(RAYCOH_KEY_KIND_ENUM) };
#undef RAYCOH_KEY_KIND_ENUM

// The encoder name of a kind ("none" for KeyKind::None).
inline const char* key_kind_name(KeyKind kind) {
#define RAYCOH_KEY_KIND_NAME(kind_, name, code) \
  if (kind == KeyKind::kind_) return name;
  RAYCOH_KEY_KINDS(RAYCOH_KEY_KIND_NAME)
#undef RAYCOH_KEY_KIND_NAME
  return "none";
}

// Every kind with a key function, in the list's order.
inline constexpr KeyKind kKeyKinds[] = {
#define RAYCOH_KEY_KIND_VALUE(kind, name, code) KeyKind::kind,
    RAYCOH_KEY_KINDS(RAYCOH_KEY_KIND_VALUE)
#undef RAYCOH_KEY_KIND_VALUE
};

// "origin, reis, ...": the kinds' encoder names, for the messages that list what runs on the GPU.
inline std::string key_kind_names() {
  std::string out;
  for (KeyKind kind : kKeyKinds) out += (out.empty() ? "" : ", ") + std::string(key_kind_name(kind));
  return out;
}

// The 64-bit code of one ray under kind Kind (the key is its top `bits` bits: key_from_code).
template <KeyKind Kind>
RAYCOH_HD RAYCOH_INLINE uint64_t key_code(const KeyArgs& a, const Ray& r) {
#define RAYCOH_KEY_KIND_CODE(kind, name, code) \
  if constexpr (Kind == KeyKind::kind) return code;
  RAYCOH_KEY_KINDS(RAYCOH_KEY_KIND_CODE)
#undef RAYCOH_KEY_KIND_CODE
  return 0;
}

// Calls f(std::integral_constant<KeyKind, K>{}) for the kind K (none for KeyKind::None); returns whether the kind
// has a key function.
template <class F>
bool with_key_kind(KeyKind kind, F&& f) {
#define RAYCOH_KEY_KIND_CALL(kind_, name, code)           \
  if (kind == KeyKind::kind_) {                           \
    f(std::integral_constant<KeyKind, KeyKind::kind_>{}); \
    return true;                                          \
  }
  RAYCOH_KEY_KINDS(RAYCOH_KEY_KIND_CALL)
#undef RAYCOH_KEY_KIND_CALL
  return false;
}

}  // namespace raycoh
