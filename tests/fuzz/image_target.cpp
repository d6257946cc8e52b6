// Fuzz target of the image files `raycoh compare` (and quality's --reference) reads: PFM (shading/image.cpp) and
// EXR through OpenImageIO (oiio/image_codec.cpp), both behind read_image (shading/image_io.cpp).
#include <string>

#include "shading/image.h"
#include "tests/fuzz/fuzz_targets.h"
#include "tests/fuzz/fuzz_util.h"

namespace raycoh::fuzz {

// First byte even: the rest is image.pfm, odd: image.exr (refused with a clear error in builds without image I/O).
void fuzz_compare_image(const uint8_t* data, size_t size) {
  if (size < 1) return;
  clear_scratch();
  const std::string name = data[0] % 2 == 0 ? "image.pfm" : "image.exr";
  const std::string path = write_scratch(name, std::string(reinterpret_cast<const char*>(data) + 1, size - 1));
  expect_clean(name, [&] { read_image(path); });
}

}  // namespace raycoh::fuzz
