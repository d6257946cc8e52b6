// Image files by extension: .pfm here through image.cpp, .exr and .png encoded and decoded by the OpenImageIO
// adapter (oiio/image_codec.h; one adapter per third-party API), written here.
//
// Built with RAYCOH_IMAGE_IO=1 (CMake option RAYCOH_IMAGE_IO, default ON). Without it OIIO is not linked, .pfm
// still works, and .exr/.png are a raycoh::Error naming the option.
//
//   .exr  32-bit float RGB, zip compression (lossless: a written reference reads back bit for bit)
//   .png  8-bit sRGB after tone mapping (shading/image.h ToneMap), values rounded to nearest
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/durable_file.h"
#include "core/error.h"
#include "oiio/image_codec.h"
#include "shading/image.h"

namespace raycoh {

namespace {

std::string extension_of(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

[[noreturn]] void no_image_io(const std::string& path) {
  throw Error(path +
              ": EXR and PNG need a build with -DRAYCOH_IMAGE_IO=ON (OpenImageIO); this build reads and "
              "writes only .pfm");
}

// The file's bytes (`path` only chooses the format): a .png is tone-mapped with tm to 8 bits first.
std::string encode(const Image& image, const std::string& path, bool png, const ToneMap& tm) {
  if (!png) return encode_exr(path, image.width, image.height, image.rgb.data());
  std::vector<unsigned char> bytes(image.rgb.size());
  for (size_t i = 0; i < bytes.size(); ++i)
    bytes[i] = static_cast<unsigned char>(std::lround(255.f * tone_map_channel(image.rgb[i], tm)));
  return encode_png(path, image.width, image.height, bytes.data());
}

}  // namespace

void check_output_image_path(const std::string& what, const std::string& path) {
  const std::string ext = extension_of(path);
  if (ext != ".pfm" && ext != ".exr" && ext != ".png")
    throw Error(what + " " + path + ": unknown image extension '" + ext + "'; valid: .exr, .png, .pfm");
  if (ext != ".pfm" && !image_io_available()) no_image_io(what + " " + path);
}

void write_image(const Image& image, const std::string& path, const ToneMap& tm) {
  check_output_image_path("image", path);
  const std::string ext = extension_of(path);
  if (image.empty()) throw Error(path + ": cannot write an empty image");
  std::error_code ec;
  if (std::filesystem::path(path).has_parent_path())
    std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
  if (ext == ".pfm") {
    write_pfm(image, path);
  } else {
    write_file_atomically(path, encode(image, path, ext == ".png", tm));
  }
}

std::string png_bytes(const Image& image, const ToneMap& tm) {
  if (!image_io_available()) throw Error("PNG output needs image I/O (this build has RAYCOH_IMAGE_IO=OFF)");
  return encode(image, "image.png", true, tm);
}

Image read_image(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw Error(path + ": no such image file");
  const std::string ext = extension_of(path);
  if (ext == ".pfm") return read_pfm(path);
  if (ext != ".exr") throw Error(path + ": cannot read '" + ext + "' images; valid: .exr, .pfm");
  if (!image_io_available()) no_image_io(path);
  RgbFloatImage file = read_rgb_float(path);
  Image img;
  img.width = file.width;
  img.height = file.height;
  img.rgb = std::move(file.rgb);
  return img;
}

}  // namespace raycoh
