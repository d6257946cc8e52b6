#include "generators/pixel_order.h"

#include <algorithm>
#include <fmt/format.h>

#include "core/error.h"
#include "core/params.h"

namespace raycoh {

std::vector<std::string> ray_order_names() { return {"scanline", "tile"}; }

RayOrder parse_ray_order(const std::string& name) {
  if (name == "scanline") return RayOrder::Scanline;
  if (name == "tile") return RayOrder::Tile;
  throw Error(fmt::format("unknown ray order '{}'; valid orders: {}", name, join(ray_order_names())));
}

const char* to_string(RayOrder order) { return order == RayOrder::Scanline ? "scanline" : "tile"; }

std::vector<uint32_t> make_pixel_order(int width, int height, RayOrder order, int tile_w, int tile_h) {
  std::vector<uint32_t> out;
  out.reserve(static_cast<size_t>(width) * height);
  if (order == RayOrder::Scanline) {
    for (int i = 0; i < width * height; ++i) out.push_back(static_cast<uint32_t>(i));
    return out;
  }
  for (int ty = 0; ty < height; ty += tile_h)
    for (int tx = 0; tx < width; tx += tile_w)
      for (int y = ty; y < std::min(ty + tile_h, height); ++y)
        for (int x = tx; x < std::min(tx + tile_w, width); ++x) out.push_back(static_cast<uint32_t>(y * width + x));
  return out;
}

}  // namespace raycoh
