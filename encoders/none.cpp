// None: no reordering. Rays are traced in the order the generator wrote them (tile-major by default, docs/design.md
// section 1), so every reordering method is measured against the free coherence of compact pixel blocks.
// It makes no keys (key_bits() = 0) and reorder() leaves the batch alone at zero cost.
//
// Parameters: none (none_params() is empty).
#include "encoders/key_encoder.h"

namespace raycoh {
namespace {

class NoneEncoder final : public Encoder {
 public:
  explicit NoneEncoder(const Bounds& box) : Encoder("none", box) {}
  void encode(const RayBatch&, uint64_t*) const override {}
  int key_bits() const override { return 0; }
  std::string params() const override { return {}; }
  KeyRecipe recipe() const override {
    KeyRecipe r;
    r.box = box();
    return r;
  }
};

}  // namespace

const ParamTable& none_params() {
  static const ParamTable table;
  return table;
}

std::unique_ptr<Encoder> make_none_encoder(ParamSet& params, const EncoderContext& context) {
  params.finish();
  return std::make_unique<NoneEncoder>(context.bounds);
}

}  // namespace raycoh
