// NoOpt: the baseline. Every hit pixel samples its own material lobe (core/bsdf.h: cosine-weighted for diffuse,
// GGX visible normals for glossy/specular, Fresnel-chosen reflection/refraction for transmissive) with random
// numbers rng(seed, frame, pixel, kDimSecondary0/1, kDimSecondaryLobe), and the ray leaves from the hit point
// offset along the geometric normal (Waechter & Binder) on the side the direction goes.
//
// Parameters: noopt_params() below. NoOpt gets the same compact tile order as every generator (DESIGN.md
// section 1), so no speedup is inflated by a scanline baseline.
#include "generators/noopt.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "core/bsdf.h"
#include "core/own_lobe.h"
#include "core/rng.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "generators/tiles.h"

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
  // Scanline order is the tile order with one-row tiles; either way tiles are filled in parallel.
  const TileGrid grid = order_ == RayOrder::Scanline
                            ? TileGrid(gbuffer.width, gbuffer.height, gbuffer.width, 1)
                            : TileGrid(gbuffer.width, gbuffer.height, tile_.first, tile_.second);
  const std::vector<uint32_t> offsets = tile_hit_offsets(gbuffer, grid);
  out.width = gbuffer.width;
  out.height = gbuffer.height;
  out.frame = gbuffer.frame;
  out.resize(offsets.back());
  const uint32_t frame = gbuffer.frame;
  tbb::enumerable_thread_specific<GenerationStats> partial;
  tbb::parallel_for(tbb::blocked_range<int>(0, grid.count(), 16), [&](const tbb::blocked_range<int>& range) {
    GenerationStats& local = partial.local();
    for (int t = range.begin(); t < range.end(); ++t) {
      int x0, y0, w, h;
      grid.rect(t, x0, y0, w, h);
      uint32_t slot = offsets[t];
      for (int y = y0; y < y0 + h; ++y)
        for (int x = x0; x < x0 + w; ++x) {
          const uint32_t p = static_cast<uint32_t>(y * gbuffer.width + x);
          const ShadingPoint& sp = gbuffer.points[p];
          if (!sp.valid()) continue;
          const DirectionSample s = sample_own_lobe(bsdf_params(scene.materials[sp.material]), sp, seed, frame, p);
          tally_ray(emit_ray(out, slot, sp, p, s), local);
          ++slot;
        }
    }
  });
  stats = GenerationStats{};
  for (const GenerationStats& s : partial) merge_stats(stats, s);
}

}  // namespace raycoh
