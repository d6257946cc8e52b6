// What the key-based encoders share: one class template that runs a per-ray code function (encoders/keys.h)
// inline in a oneTBB loop, so a batch costs one virtual call; the `bits` parameter; and the factory that each
// encoder's file defines (registry.cpp dispatches to them).
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <memory>
#include <string>
#include <utility>

#include "encoders/encoder.h"
#include "encoders/key_recipe.h"
#include "encoders/keys.h"

namespace raycoh {

template <class CodeFn>
class KeyEncoder final : public Encoder {
 public:
  KeyEncoder(std::string name, const KeyRecipe& recipe, std::string params, CodeFn code, std::string details)
      : Encoder(std::move(name), recipe.box),
        recipe_(recipe),
        params_(std::move(params)),
        details_(std::move(details)),
        code_(std::move(code)) {}

  void encode(const RayBatch& batch, uint64_t* keys) const override {
    const Ray* rays = batch.rays.data();
    // Keys are independent per ray; 4096 rays per task keeps the scheduling cost far below the work.
    tbb::parallel_for(tbb::blocked_range<size_t>(0, batch.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i < r.end(); ++i) keys[i] = key_from_code(code_(rays[i]), recipe_.bits);
    });
  }
  int key_bits() const override { return recipe_.bits; }
  std::string params() const override { return params_; }
  std::string details() const override { return details_; }
  KeyRecipe recipe() const override { return recipe_; }

 private:
  KeyRecipe recipe_;
  std::string params_;
  std::string details_;
  CodeFn code_;
};

// code(const Ray&) -> uint64_t is the 64-bit code of one ray.
template <class CodeFn>
std::unique_ptr<Encoder> make_key_encoder(std::string name, const KeyRecipe& recipe, std::string params, CodeFn code,
                                          std::string details = {}) {
  return std::make_unique<KeyEncoder<CodeFn>>(std::move(name), recipe, std::move(params), std::move(code),
                                              std::move(details));
}

// A key encoder whose code is its recipe's key function (encoders/key_code.h), the one the GPU's key kernel runs.
// cuts: mlhcc's cut table view; keep: what that view points into (the encoder keeps it alive).
inline std::unique_ptr<Encoder> make_recipe_encoder(std::string name, const KeyRecipe& recipe, std::string params,
                                                    const MlhccCuts& cuts = {}, std::shared_ptr<const void> keep = {},
                                                    std::string details = {}) {
  const KeyArgs args = key_args(recipe, cuts);
  std::unique_ptr<Encoder> out;
  with_key_kind(recipe.kind, [&](auto kind) {
    constexpr KeyKind K = decltype(kind)::value;
    out = make_key_encoder(
        std::move(name), recipe, std::move(params), [args, keep](const Ray& r) { return key_code<K>(args, r); },
        std::move(details));
  });
  return out;  // null for KeyKind::None: such an encoder brings its own code function (make_key_encoder)
}

// The rows several encoders share: bits (the key is the code's top `bits` bits) and L (end-point distance).
ParamSpec key_bits_param();
ParamSpec end_point_param();
// Reads the bits row: 32 or 64.
int read_key_bits(ParamSet& params);
// Checks that every given parameter was used, then returns the canonical set with ",box=..." appended.
std::string finish_encoder_params(ParamSet& params, const Bounds& box);

// One parameter table and one factory per encoder file.
const ParamTable& none_params();
std::unique_ptr<Encoder> make_none_encoder(ParamSet& params, const EncoderContext& context);
const ParamTable& origin_params();
std::unique_ptr<Encoder> make_origin_encoder(ParamSet& params, const EncoderContext& context);
const ParamTable& reis_params();
std::unique_ptr<Encoder> make_reis_encoder(ParamSet& params, const EncoderContext& context);
const ParamTable& costa_params();
std::unique_ptr<Encoder> make_costa_encoder(ParamSet& params, const EncoderContext& context);
const ParamTable& aila_params();
std::unique_ptr<Encoder> make_aila_encoder(ParamSet& params, const EncoderContext& context);
const ParamTable& twopoint_params();
std::unique_ptr<Encoder> make_twopoint_encoder(ParamSet& params, const EncoderContext& context);
const ParamTable& mlhcc_params();
std::unique_ptr<Encoder> make_mlhcc_encoder(ParamSet& params, const EncoderContext& context);
const ParamTable& window_params();
std::unique_ptr<Encoder> make_window_encoder(ParamSet& params, const EncoderContext& context);

}  // namespace raycoh
