// Screen tiles, one definition for the CPU generators and the CUDA block phases (one block per tile).
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/platform.h"

namespace raycoh {

// The order in which a generator writes its rays into the batch (docs/design.md section 1), one enum for every
// generator and the CUDA block phases: scanline (the image's rows), tile (W x H tiles in row-major tile order,
// row-major inside a tile), group (tiles as in tile order, whole groups one after the other inside a tile; only
// the grouping generators have groups, so for a pixel order it is tile order).
enum class RayOrder { Scanline, Tile, Group };

// Pixel rectangle of one tile; pixel number i of the tile counts row-major inside it.
struct TileRect {
  int x0 = 0, y0 = 0, w = 0, h = 0;
  RAYCOH_HD uint32_t area() const { return static_cast<uint32_t>(w * h); }
  // Image index (y * image_width + x) of pixel number i.
  RAYCOH_HD uint32_t pixel(uint32_t i, int image_width) const {
    return static_cast<uint32_t>((y0 + static_cast<int>(i) / w) * image_width + x0 + static_cast<int>(i) % w);
  }
};

// W x H tiles covering the image in row-major tile order; tiles at the right and bottom borders are clipped.
struct TileGrid {
  int width = 0, height = 0, tile_w = 8, tile_h = 8, tiles_x = 0, tiles_y = 0;
  TileGrid() = default;
  RAYCOH_HD TileGrid(int w, int h, int tw, int th)
      : width(w), height(h), tile_w(tw), tile_h(th), tiles_x((w + tw - 1) / tw), tiles_y((h + th - 1) / th) {}
  RAYCOH_HD int count() const { return tiles_x * tiles_y; }
  RAYCOH_HD TileRect rect(int t) const {
    TileRect r;
    r.x0 = (t % tiles_x) * tile_w;
    r.y0 = (t / tiles_x) * tile_h;
    r.w = tile_w < width - r.x0 ? tile_w : width - r.x0;
    r.h = tile_h < height - r.y0 ? tile_h : height - r.y0;
    return r;
  }
  RAYCOH_HD void rect(int t, int& x0, int& y0, int& w, int& h) const {
    const TileRect r = rect(t);
    x0 = r.x0;
    y0 = r.y0;
    w = r.w;
    h = r.h;
  }
  // Position of pixel (x, y) in the tile-major order of every pixel (make_pixel_order's tile order): the pixels
  // of the tile rows above, of the tiles to the left in its tile row, then row-major inside its clipped tile.
  RAYCOH_HD size_t tile_major_slot(int x, int y) const {
    const int row0 = (y / tile_h) * tile_h, col0 = (x / tile_w) * tile_w;
    const int h = tile_h < height - row0 ? tile_h : height - row0;
    const int w = tile_w < width - col0 ? tile_w : width - col0;
    return static_cast<size_t>(row0) * width + static_cast<size_t>(col0) * h + static_cast<size_t>(y - row0) * w +
           static_cast<size_t>(x - col0);
  }
};

}  // namespace raycoh
