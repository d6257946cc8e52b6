// The two prior-art generators that share random numbers between pixels (the ancestors of `ours`):
//
//   sadeghi      Sadeghi, Chen & Jensen, "Coherent Path Tracing" (JGT 2009): every pixel of the image uses the
//                same random numbers in a frame, so pixels with the same material and frame sample the same
//                tangent-space direction. With interleave=N (Keller & Heidrich's interleaved sampling, which the
//                paper uses against the structured error of one shared sample) pixel (x, y) uses stream
//                (y mod N) N + (x mod N) of N^2 shared streams. N = 1: one sample for the whole image.
//   microjitter  Dufay, Lecocq, Pacanowski, Iehl & Poulin, "Cache-Friendly Micro-Jittered Sampling" (SIGGRAPH
//                2016 talk): one shared sample per frame, jittered per pixel within a small radius: pixel p uses
//                u_p = frac(u + radius (xi_p - 1/2)) per dimension, with u shared and xi_p the pixel's own
//                (NoOpt's) random numbers. A toroidal shift of a uniform u is uniform whatever the shift, so u_p
//                is uniform; radius = 1 decorrelates the pixels completely.
// Both sample every pixel's own BSDF (core/bsdf.h sample_direction) with those numbers, so each pixel's marginal
// is exactly its BSDF's (unbiased; tests/shared_sample_test.cpp checks it like `ours`); only the correlation
// between pixels changes. Batch order and tiles as NoOpt (order=tile, tile=8x8 by default); every ray counts as
// reused (its random numbers came from a shared stream) except with interleave=N where N^2 >= pixels.
// The numbers rule is generators/shared_sample.h's, which the device kernel (cuda/device_per_pixel.cu) calls too:
// device_recipe() hands it over typed (DeviceRecipe::Kind::SharedSample).
//
// Parameters: sadeghi_params() and microjitter_params() below.
#include "generators/shared_sample.h"

#include "generators/emit_per_pixel.h"
#include "generators/grouping.h"

namespace raycoh {
namespace {

class SharedSampleGenerator final : public Generator {
 public:
  SharedSampleGenerator(ParamSet& params, Sharing sharing) {
    config_.sharing = sharing;
    order_ = parse_ray_order(params.get_choice("order"));
    tile_ = params.get_size("tile");
    if (sharing == Sharing::Sadeghi)
      config_.interleave = static_cast<uint32_t>(params.get_int("interleave"));
    else
      config_.radius = params.get_float("radius");
    params.finish();
    params_ = params.canonical();
  }

  std::string params() const override { return params_; }

  void generate(const Scene& scene, const GBuffer& gbuffer, uint32_t seed, RayBatch& out,
                GenerationStats& stats) override {
    const MaterialTable materials(scene, gbuffer);
    const bool all_own = shared_sample_all_own(config_, gbuffer.width, gbuffer.height);
    emit_per_valid_pixel(gbuffer, order_, tile_, out, stats,
                         [&](int x, int y, uint32_t p, const ShadingPoint& sp, GenerationStats& local) {
                           if (!all_own) ++local.reused_rays;
                           return shared_sample_direction(config_, materials[sp.material], sp, seed, gbuffer.frame,
                                                          static_cast<uint32_t>(x), static_cast<uint32_t>(y), p);
                         });
  }

  // The typed configuration the device kernel runs (cuda/device_generators.h).
  DeviceRecipe device_recipe() const override {
    DeviceRecipe r;
    r.kind = DeviceRecipe::Kind::SharedSample;
    r.tile_w = tile_.first;
    r.tile_h = tile_.second;
    r.order = order_;
    r.shared = config_;
    return r;
  }

 private:
  SharedSampleConfig config_;
  RayOrder order_;
  std::pair<int, int> tile_;
  std::string params_;
};

}  // namespace

const ParamTable& sadeghi_params() {
  static const ParamTable table = {
      choice_param("order", "tile", ray_order_names(), "batch order: the image's rows, or W x H tiles"),
      size_param("tile", {8, 8}, 1, 4096, "tile of the tile order"),
      int_param("interleave", 1, 1, 4096, "N: N x N interleaved shared streams (1: one sample for the image)"),
  };
  return table;
}

const ParamTable& microjitter_params() {
  static const ParamTable table = {
      choice_param("order", "tile", ray_order_names(), "batch order: the image's rows, or W x H tiles"),
      size_param("tile", {8, 8}, 1, 4096, "tile of the tile order"),
      float_param("radius", 0.05f, 0.f, 1.f, "jitter width in sample space per dimension (1: independent pixels)"),
  };
  return table;
}

std::unique_ptr<Generator> make_sadeghi_generator(ParamSet& params) {
  return std::make_unique<SharedSampleGenerator>(params, Sharing::Sadeghi);
}

std::unique_ptr<Generator> make_microjitter_generator(ParamSet& params) {
  return std::make_unique<SharedSampleGenerator>(params, Sharing::MicroJitter);
}

}  // namespace raycoh
