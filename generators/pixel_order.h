// The order in which pixels (and so their rays) are written into a batch (docs/design.md section 1).
//   scanline: row by row.
//   tile:     W x H tiles in row-major tile order, row-major inside a tile; partial tiles at the right and
//             bottom borders are clipped to the image and keep the same inner order.
//   group:    the grouping generators' order (core/tile_grid.h); as a pixel order, tile order.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/tile_grid.h"

namespace raycoh {

RayOrder parse_ray_order(const std::string& name);  // throws raycoh::Error naming the valid orders
const char* to_string(RayOrder order);
// scanline, tile, and with groups (the grouping generators) group.
std::vector<std::string> ray_order_names(bool with_groups = false);

// order[i] = pixel index (y * width + x) of the i-th pixel in batch order; a permutation of [0, width*height).
std::vector<uint32_t> make_pixel_order(int width, int height, RayOrder order, int tile_w, int tile_h);

}  // namespace raycoh
