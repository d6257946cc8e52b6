// NoOpt: the baseline. Every hit pixel samples its own material lobe (core/bsdf.h: cosine-weighted for diffuse,
// GGX visible normals for glossy/specular, Fresnel-chosen reflection/refraction for transmissive) with random
// numbers rng(seed, frame, pixel, kDimSecondary0/1, kDimSecondaryLobe), and the ray leaves from the hit point
// offset along the geometric normal (Waechter & Binder) on the side the direction goes.
//
// Parameters
//   order  string  tile      scanline | tile: batch order (DESIGN.md section 1; NoOpt gets the same compact
//                            tile order as every generator, so no speedup is inflated by a scanline baseline)
//   tile   WxH     8x8       [1, 4096] each: tile of the tile order
#include <tbb/parallel_for.h>

#include "core/bsdf.h"
#include "core/rng.h"
#include "generators/generator.h"
#include "generators/noopt.h"
#include "generators/pixel_order.h"

namespace raycoh {

NoOptGenerator::NoOptGenerator(ParamSet& params) {
  order_ = parse_ray_order(params.get_choice("order", "tile", ray_order_names()));
  tile_ = params.get_size("tile", {8, 8}, 1, 4096);
  params.finish();
  params_ = params.canonical();
}

void NoOptGenerator::generate(const Scene& scene, const GBuffer& gbuffer, uint32_t seed, RayBatch& out,
                              GenerationStats& stats) {
  if (order_cache_width_ != gbuffer.width || order_cache_height_ != gbuffer.height) {
    pixel_order_ = make_pixel_order(gbuffer.width, gbuffer.height, order_, tile_.first, tile_.second);
    order_cache_width_ = gbuffer.width;
    order_cache_height_ = gbuffer.height;
  }
  const std::vector<uint32_t> pixels = hit_pixels_in_order(gbuffer, pixel_order_);
  out.width = gbuffer.width;
  out.height = gbuffer.height;
  out.frame = gbuffer.frame;
  out.resize(pixels.size());
  const uint32_t frame = gbuffer.frame;
  std::vector<uint32_t> flags(pixels.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels.size(), 2048), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) {
      const uint32_t p = pixels[i];
      const ShadingPoint& sp = gbuffer.points[p];
      const BsdfParams m = bsdf_params(scene.materials[sp.material]);
      const DirectionSample s =
          sample_direction(m, sp.ns, sp.ng, sp.wo, sp.front_face, rng_float(seed, frame, p, kDimSecondary0),
                           rng_float(seed, frame, p, kDimSecondary1), rng_float(seed, frame, p, kDimSecondaryLobe));
      flags[i] = emit_ray(out, i, sp, p, s);
    }
  });
  stats = GenerationStats{};
  count_flags(flags, stats);
}

}  // namespace raycoh
