// Image files encoded and decoded in memory: the one OpenImageIO adapter (each third-party API is confined to one
// adapter, so an upgrade touches one place). It sits low, beside core/, so that both of its users can reach it:
// scenes/ decodes glTF textures with it, and shading/image_io.cpp reads and writes EXR and PNG files through it.
// Plain pixel buffers only: the Image type, tone mapping and the file-path rules (extensions, atomic writes) are
// shading's (shading/image.h).
//
// Built with RAYCOH_IMAGE_IO=1 (CMake option RAYCOH_IMAGE_IO, default ON). Without it OpenImageIO is not linked:
// image_io_available() is false, decode_rgba8 says why it cannot decode, and the encode and read functions throw
// raycoh::Error naming the option.
//
//   .exr  32-bit float RGB, zip compression (lossless: a written reference reads back bit for bit)
//   .png  8-bit RGB as given (shading/image_io.cpp tone-maps before encoding)
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace raycoh {

// True when this build reads and writes EXR/PNG (RAYCOH_IMAGE_IO=ON).
bool image_io_available();

// An 8-bit RGBA image decoded from an encoded file's bytes (scene textures: PNG, JPEG, WebP): grey is replicated
// and missing alpha is 255. Returns false and says why when the bytes cannot be decoded, or when this build has
// no image I/O (RAYCOH_IMAGE_IO=OFF).
struct Rgba8Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgba;
};
bool decode_rgba8(const unsigned char* bytes, size_t size, Rgba8Image& out, std::string& why);

// The bytes of an image file of width x height RGB pixels (row-major, y = 0 at the top), in the format of path's
// extension; path names the file in messages and is not written. encode_exr takes 3 floats per pixel, encode_png
// 3 bytes. Throws raycoh::Error when OpenImageIO cannot encode it.
std::string encode_exr(const std::string& path, int width, int height, const float* rgb);
std::string encode_png(const std::string& path, int width, int height, const unsigned char* rgb);

// An image file's pixels as float RGB (3 per pixel; a single channel is replicated, alpha is dropped). Throws
// raycoh::Error when the file cannot be read or is not a 2-D image.
struct RgbFloatImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
};
RgbFloatImage read_rgb_float(const std::string& path);

}  // namespace raycoh
