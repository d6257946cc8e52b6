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

 private:
  RayOrder order_;
  std::pair<int, int> tile_;
  std::string params_;
};

}  // namespace raycoh
