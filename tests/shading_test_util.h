// Helpers shared by the shading tests (image, metrics, path tracer, reference cache, quality commands).
#pragma once

#include "shading/image.h"
#include "shading/path_tracer.h"

namespace raycoh::test {

inline Image filled(int w, int h, Vec3 v) { return Image(w, h, v); }

// Every pixel different, with extreme values in pixel (0, 0): files must keep them bit for bit.
inline Image test_pattern(int w, int h) {
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      img.set(x, y, {0.1f * static_cast<float>(x), 1e-3f * static_cast<float>(y * y), x == y ? 17.25f : 0.5f});
  img.set(0, 0, {1e-30f, 3.4e38f, 0.f});
  return img;
}

inline RenderSettings small(int w, int h, uint32_t seed = 1) {
  RenderSettings rs;
  rs.width = w;
  rs.height = h;
  rs.seed = seed;
  return rs;
}

}  // namespace raycoh::test
