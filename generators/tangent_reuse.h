// The paper's generator (`ours`) and its contiguous-group ablation (`contiguous`); see tangent_reuse.cpp.
#pragma once

#include <string>
#include <utility>

#include "generators/generator.h"
#include "generators/grouping.h"

namespace raycoh {

class TangentSpaceReuse final : public Generator {
 public:
  // interleaved = true: `ours` (shuffled, per-frame groups); false: `contiguous` (contiguous groups).
  TangentSpaceReuse(ParamSet& params, bool interleaved);
  void generate(const Scene& scene, const GBuffer& gbuffer, uint32_t seed, RayBatch& out,
                GenerationStats& stats) override;
  std::string params() const override { return params_; }
  DeviceRecipe device_recipe() const override;
  std::optional<BatchLayout> layout() const override;
  // The grouping of one frame, as the CPU loop and the CUDA block phases read it: device_recipe().config().
  GroupingConfig config(uint32_t seed, uint32_t frame) const { return device_recipe().config(seed, frame); }
  std::pair<int, int> tile() const { return tile_; }

 private:
  bool interleaved_;
  std::pair<int, int> tile_;
  int k_ = 8;
  RayOrder order_ = RayOrder::Tile;
  uint32_t salt_ = 0;
  HybridRule hybrid_ = HybridRule::Paper;
  ReuseFrame frame_ = ReuseFrame::Duff;
  std::string params_;
};

class DirectReuse final : public Generator {
 public:
  explicit DirectReuse(ParamSet& params);
  void generate(const Scene& scene, const GBuffer& gbuffer, uint32_t seed, RayBatch& out,
                GenerationStats& stats) override;
  std::string params() const override { return params_; }

 private:
  std::pair<int, int> tile_;
  std::string params_;
};

// Parameter tables and factories: `ours` and `contiguous` share ours_params() (tangent_reuse.cpp), `direct`
// has direct_params() (direct_reuse.cpp).
const ParamTable& ours_params();
std::unique_ptr<Generator> make_ours_generator(ParamSet& params);
std::unique_ptr<Generator> make_contiguous_generator(ParamSet& params);
const ParamTable& direct_params();
std::unique_ptr<Generator> make_direct_generator(ParamSet& params);

}  // namespace raycoh
