// The tile-major emit loop of the generators whose pixels sample on their own (noopt, sadeghi, microjitter): one
// ray per valid pixel, tiles in parallel, each tile's rays in row-major order from the tile's slot in the batch.
#pragma once

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <utility>

#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "generators/tiles.h"

namespace raycoh {

// Fills `out` and `stats`. Scanline order is the tile order with one-row tiles. sample(x, y, p, sp, local) returns
// pixel p's DirectionSample and may count into `local` (the thread's GenerationStats) beyond what tally_ray counts.
template <class Sample>
void emit_per_valid_pixel(const GBuffer& gbuffer, RayOrder order, std::pair<int, int> tile, RayBatch& out,
                          GenerationStats& stats, Sample&& sample) {
  const TileGrid grid = order == RayOrder::Scanline ? TileGrid(gbuffer.width, gbuffer.height, gbuffer.width, 1)
                                                    : TileGrid(gbuffer.width, gbuffer.height, tile.first, tile.second);
  const std::vector<uint32_t> offsets = tile_hit_offsets(gbuffer, grid);
  out.width = gbuffer.width;
  out.height = gbuffer.height;
  out.frame = gbuffer.frame;
  out.resize(offsets.back());
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
          tally_ray(emit_ray(out, slot, sp, p, sample(x, y, p, sp, local)), local);
          ++slot;
        }
    }
  });
  stats = GenerationStats{};
  for (const GenerationStats& s : partial) merge_stats(stats, s);
}

}  // namespace raycoh
