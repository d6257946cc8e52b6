#include "generators/pixel_order.h"

#include <fmt/format.h>

#include "core/error.h"
#include "core/params.h"
#include "core/tile_grid.h"

namespace raycoh {

std::vector<std::string> ray_order_names(bool with_groups) {
  if (with_groups) return {"tile", "group", "scanline"};
  return {"scanline", "tile"};
}

RayOrder parse_ray_order(const std::string& name) {
  if (name == "scanline") return RayOrder::Scanline;
  if (name == "tile") return RayOrder::Tile;
  if (name == "group") return RayOrder::Group;
  throw Error(fmt::format("unknown ray order '{}'; valid orders: {}", name, join(ray_order_names(true))));
}

const char* to_string(RayOrder order) {
  switch (order) {
    case RayOrder::Scanline:
      return "scanline";
    case RayOrder::Tile:
      return "tile";
    case RayOrder::Group:
      return "group";
  }
  return "tile";
}

std::vector<uint32_t> make_pixel_order(int width, int height, RayOrder order, int tile_w, int tile_h) {
  std::vector<uint32_t> out;
  out.reserve(static_cast<size_t>(width) * height);
  if (order == RayOrder::Scanline) {
    for (int i = 0; i < width * height; ++i) out.push_back(static_cast<uint32_t>(i));
    return out;
  }
  const TileGrid grid(width, height, tile_w, tile_h);  // the grid the GPU inverts (TileGrid::tile_major_slot)
  for (int t = 0; t < grid.count(); ++t) {
    const TileRect r = grid.rect(t);
    for (uint32_t i = 0; i < r.area(); ++i) out.push_back(r.pixel(i, width));
  }
  return out;
}

}  // namespace raycoh
