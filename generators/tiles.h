// Screen tiles and the per-tile pixel-number shuffle of the paper's interleaved grouping (section 3.3).
#pragma once

#include <cstdint>
#include <vector>

#include "core/ray_batch.h"
#include "core/tile_grid.h"
#include "core/tile_shuffle.h"

namespace raycoh {

// Hit pixels per tile and the batch slot where each tile's rays start in a tile-major batch (size count + 1).
std::vector<uint32_t> tile_hit_offsets(const GBuffer& gbuffer, const TileGrid& grid);

// For a scanline-ordered batch: the slot of every hit pixel (rank among hit pixels in scanline order).
std::vector<uint32_t> scanline_slots(const GBuffer& gbuffer);

}  // namespace raycoh
