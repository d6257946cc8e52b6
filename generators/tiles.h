// Screen tiles and the per-tile pixel-number shuffle of the paper's interleaved grouping (section 3.3).
#pragma once

#include <cstdint>
#include <vector>

#include "generators/ray_batch.h"

namespace raycoh {

// W x H tiles covering the image in row-major tile order; tiles at the right and bottom borders are clipped.
struct TileGrid {
  int width = 0, height = 0, tile_w = 8, tile_h = 8, tiles_x = 0, tiles_y = 0;
  TileGrid(int width, int height, int tile_w, int tile_h);
  int count() const { return tiles_x * tiles_y; }
  // Pixel rectangle of tile t.
  void rect(int t, int& x0, int& y0, int& w, int& h) const;
};

// Shuffle of the pixel numbers 0..m-1 of one tile: s = (a i + c) mod M on M = the smallest power of two >= m,
// re-applied while s >= m ("cycle walking"). With a = 1 (mod 4) and c odd, the affine map is a full-period
// (single-cycle) LCG on [0, M) by the Hull-Dobell theorem, and walking it restricts that single cycle to
// [0, m), so the shuffle stays a full-period bijection for any m, power of two or not. a and c are drawn from
// rng(seed, frame, tile, kDimTileShuffleA/C); a = 1 is excluded for M >= 8 because it would only rotate the
// numbering and leave groups contiguous.
struct TileShuffle {
  uint32_t a = 1, c = 0, mask = 0, m = 1;
  uint32_t operator()(uint32_t i) const {
    uint32_t s = (a * i + c) & mask;
    while (s >= m) s = (a * s + c) & mask;
    return s;
  }
};
TileShuffle make_tile_shuffle(uint32_t m, uint32_t seed, uint32_t frame, uint32_t tile);

// Hit pixels per tile and the batch slot where each tile's rays start in a tile-major batch (size count + 1).
std::vector<uint32_t> tile_hit_offsets(const GBuffer& gbuffer, const TileGrid& grid);

// For a scanline-ordered batch: the slot of every hit pixel (rank among hit pixels in scanline order).
std::vector<uint32_t> scanline_slots(const GBuffer& gbuffer);

}  // namespace raycoh
