// NoOpt: the baseline. Every hit pixel samples its own material lobe (core/bsdf.h: cosine-weighted for diffuse,
// GGX visible normals for glossy/specular, Fresnel-chosen reflection/refraction for transmissive) with random
// numbers rng(seed, frame, pixel, kDimSecondary0/1, kDimSecondaryLobe), and the ray leaves from the hit point
// offset along the geometric normal (Waechter & Binder) on the side the direction goes.
//
// Parameters: noopt_params() below. NoOpt gets the same compact tile order as every generator (docs/design.md
// section 1), so no speedup is inflated by a scanline baseline.
#include "generators/noopt.h"

#include "core/bsdf.h"
#include "core/own_lobe.h"
#include "generators/emit_per_pixel.h"

namespace raycoh {

const ParamTable& noopt_params() {
  static const ParamTable table = {
      choice_param("order", "tile", ray_order_names(), "batch order: the image's rows, or W x H tiles"),
      size_param("tile", {8, 8}, 1, 4096, "tile of the tile order"),
  };
  return table;
}

std::unique_ptr<Generator> make_noopt_generator(ParamSet& params) { return std::make_unique<NoOptGenerator>(params); }

NoOptGenerator::NoOptGenerator(ParamSet& params) {
  order_ = parse_ray_order(params.get_choice("order"));
  tile_ = params.get_size("tile");
  params.finish();
  params_ = params.canonical();
}

void NoOptGenerator::generate(const Scene& scene, const GBuffer& gbuffer, uint32_t seed, RayBatch& out,
                              GenerationStats& stats) {
  const MaterialTable materials(scene, gbuffer);
  emit_per_valid_pixel(gbuffer, order_, tile_, out, stats,
                       [&](int, int, uint32_t p, const ShadingPoint& sp, GenerationStats&) {
                         return sample_own_lobe(materials[sp.material], sp, seed, gbuffer.frame, p);
                       });
}

}  // namespace raycoh
