// NoOpt generator (see noopt.cpp for the method and parameters) and the per-ray helpers other generators reuse.
#pragma once

#include <utility>
#include <vector>

#include "core/bsdf.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"

namespace raycoh {

class NoOptGenerator final : public Generator {
 public:
  explicit NoOptGenerator(ParamSet& params);
  void generate(const Scene& scene, const GBuffer& gbuffer, uint32_t seed, RayBatch& out,
                GenerationStats& stats) override;
  std::string params() const override { return params_; }
  // The typed configuration the GPU version runs (cuda/device_generators.h).
  DeviceRecipe device_recipe() const override {
    DeviceRecipe r;
    r.kind = DeviceRecipe::Kind::NoOpt;
    r.tile_w = tile_.first;
    r.tile_h = tile_.second;
    r.order = order_;
    return r;
  }

 private:
  RayOrder order_;
  std::pair<int, int> tile_;
  std::string params_;
};

// The parameter table and factory of `noopt` (noopt.cpp).
const ParamTable& noopt_params();
std::unique_ptr<Generator> make_noopt_generator(ParamSet& params);

}  // namespace raycoh
