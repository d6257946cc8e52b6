#include "generators/tiles.h"

#include <tbb/parallel_for.h>

#include "core/rng.h"

namespace raycoh {

std::vector<uint32_t> tile_hit_offsets(const GBuffer& g, const TileGrid& grid) {
  std::vector<uint32_t> offsets(static_cast<size_t>(grid.count()) + 1, 0);
  tbb::parallel_for(0, grid.count(), [&](int t) {
    int x0, y0, w, h;
    grid.rect(t, x0, y0, w, h);
    uint32_t n = 0;
    for (int y = y0; y < y0 + h; ++y)
      for (int x = x0; x < x0 + w; ++x) n += g.points[static_cast<size_t>(y) * g.width + x].valid();
    offsets[static_cast<size_t>(t) + 1] = n;
  });
  for (size_t t = 1; t < offsets.size(); ++t) offsets[t] += offsets[t - 1];
  return offsets;
}

std::vector<uint32_t> scanline_slots(const GBuffer& g) {
  std::vector<uint32_t> slots(g.points.size(), 0);
  uint32_t n = 0;
  for (size_t p = 0; p < g.points.size(); ++p)
    if (g.points[p].valid()) slots[p] = n++;
  return slots;
}

}  // namespace raycoh
