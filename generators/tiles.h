// Screen tiles and the per-tile pixel-number shuffle of the paper's interleaved grouping (section 3.3).
#pragma once

#include <cstdint>
#include <vector>

#include "core/tile_shuffle.h"
#include "core/ray_batch.h"

namespace raycoh {

// W x H tiles covering the image in row-major tile order; tiles at the right and bottom borders are clipped.
struct TileGrid {
  int width = 0, height = 0, tile_w = 8, tile_h = 8, tiles_x = 0, tiles_y = 0;
  TileGrid(int width, int height, int tile_w, int tile_h);
  int count() const { return tiles_x * tiles_y; }
  // Pixel rectangle of tile t.
  void rect(int t, int& x0, int& y0, int& w, int& h) const;
};

// Hit pixels per tile and the batch slot where each tile's rays start in a tile-major batch (size count + 1).
std::vector<uint32_t> tile_hit_offsets(const GBuffer& gbuffer, const TileGrid& grid);

// For a scanline-ordered batch: the slot of every hit pixel (rank among hit pixels in scanline order).
std::vector<uint32_t> scanline_slots(const GBuffer& gbuffer);

}  // namespace raycoh
