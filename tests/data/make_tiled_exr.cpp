// One-off generator of tests/data/tiled-70x40.exr (not built; kept as its provenance): a zip-compressed, tiled
// (32 x 32) float RGBA EXR of 70 x 40 pixels whose data window starts at (5, 3); pixel (x, y) of the window holds
// (x, y, x + 100 y, 1). Build: g++ make_tiled_exr.cpp $(pkg-config --cflags --libs OpenImageIO); ./a.out F.exr
#include <OpenImageIO/imageio.h>

#include <vector>
int main(int, char** argv) {
  OIIO::ImageSpec spec(70, 40, 4, OIIO::TypeDesc::FLOAT);
  spec.x = 5;
  spec.y = 3;
  spec.full_x = 0;
  spec.full_y = 0;
  spec.full_width = 80;
  spec.full_height = 50;
  spec.tile_width = 32;
  spec.tile_height = 32;
  spec.attribute("compression", "zip");
  std::vector<float> px(70 * 40 * 4);
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 70; ++x) {
      float* p = &px[4 * (y * 70 + x)];
      p[0] = x;
      p[1] = y;
      p[2] = x + 100.0f * y;
      p[3] = 1;
    }
  auto out = OIIO::ImageOutput::create(argv[1]);
  if (!out->open(argv[1], spec) || !out->write_image(OIIO::TypeDesc::FLOAT, px.data()) || !out->close()) return 1;
  return 0;
}
