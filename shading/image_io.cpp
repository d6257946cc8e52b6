// Image files by extension: .pfm here through image.cpp, .exr and .png through OpenImageIO. This is the one file
// that includes OpenImageIO (STYLE.md: one adapter per third-party API). OIIO bundles its own fmt and defines
// FMT_EXCEPTIONS 0 when its headers come first, so nothing of fmt is included here (ECOSYSTEM.md).
//
// Built with RAYCOH_IMAGE_IO=1 (CMake option RAYCOH_IMAGE_IO, default ON). Without it OIIO is not linked, .pfm
// still works, and .exr/.png are a raycoh::Error naming the option.
//
//   .exr  32-bit float RGB, zip compression (lossless: a written reference reads back bit for bit)
//   .png  8-bit sRGB after tone mapping (shading/image.h ToneMap), values rounded to nearest
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>

#include "core/durable_file.h"
#include "core/error.h"
#include "shading/image.h"

#if RAYCOH_IMAGE_IO
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#endif

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

#if RAYCOH_IMAGE_IO
// The file's bytes, encoded in memory (OIIO's IOVecOutput proxy); `path` only chooses the format.
std::string encode_oiio(const Image& image, const std::string& path, bool png, const ToneMap& tm) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out || !out->supports("ioproxy")) throw Error(path + ": cannot write: " + OIIO::geterror());
  const OIIO::TypeDesc type = png ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT;
  OIIO::ImageSpec spec(image.width, image.height, 3, type);
  if (!png) spec.attribute("compression", "zip");
  std::vector<unsigned char> encoded;
  OIIO::Filesystem::IOVecOutput memory(encoded);
  OIIO::Filesystem::IOProxy* proxy = &memory;
  spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  std::vector<unsigned char> bytes;
  const void* data = image.rgb.data();
  if (png) {
    bytes.resize(image.rgb.size());
    for (size_t i = 0; i < bytes.size(); ++i)
      bytes[i] = static_cast<unsigned char>(std::lround(255.f * tone_map_channel(image.rgb[i], tm)));
    data = bytes.data();
  }
  if (!out->open(path, spec) || !out->write_image(type, data) || !out->close())
    throw Error(path + ": cannot encode the image: " + out->geterror());
  return std::string(encoded.begin(), encoded.end());
}

Image read_oiio(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw Error(path + ": cannot read: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width < 1 || spec.height < 1 || spec.nchannels < 1 || spec.depth > 1)
    throw Error(path + ": unsupported image (" + std::to_string(spec.width) + "x" + std::to_string(spec.height) + ", " +
                std::to_string(spec.nchannels) + " channels)");
  const int channels = std::min(spec.nchannels, 3);
  std::vector<float> data(static_cast<size_t>(spec.width) * spec.height * channels);
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, data.data()))
    throw Error(path + ": cannot read pixels: " + in->geterror());
  in->close();
  Image img(spec.width, spec.height);
  for (size_t p = 0; p < img.pixels(); ++p) {
    const float* s = &data[p * channels];
    img.set(p, channels >= 3 ? Vec3{s[0], s[1], s[2]} : Vec3(s[0]));
  }
  return img;
}
#endif

}  // namespace

bool image_io_available() { return RAYCOH_IMAGE_IO != 0; }

bool decode_rgba8([[maybe_unused]] const unsigned char* bytes, [[maybe_unused]] size_t size,
                  [[maybe_unused]] Rgba8Image& out, std::string& why) {
#if RAYCOH_IMAGE_IO
  // The format comes from the magic bytes: embedded images have no file name, and URIs may lie.
  const char* name = nullptr;
  if (size >= 8 && std::memcmp(bytes, "\x89PNG", 4) == 0) name = "texture.png";
  if (size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8) name = "texture.jpg";
  if (size >= 12 && std::memcmp(bytes, "RIFF", 4) == 0 && std::memcmp(bytes + 8, "WEBP", 4) == 0) name = "texture.webp";
  if (!name) {
    why = "not a PNG, JPEG or WebP image";
    return false;
  }
  OIIO::Filesystem::IOMemReader memory(bytes, size);
  auto in = OIIO::ImageInput::open(name, nullptr, &memory);
  if (!in) {
    why = OIIO::geterror();
    return false;
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width < 1 || spec.height < 1 || spec.nchannels < 1 || spec.depth > 1 ||
      static_cast<double>(spec.width) * spec.height > 1 << 28) {
    why = "unsupported size or channel count";
    return false;
  }
  const int channels = std::min(spec.nchannels, 4);
  const size_t pixels = static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height);
  std::vector<unsigned char> data(pixels * static_cast<size_t>(channels));
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, data.data())) {
    why = in->geterror();
    return false;
  }
  out.width = spec.width;
  out.height = spec.height;
  out.rgba.resize(pixels * 4);
  for (size_t p = 0; p < pixels; ++p) {
    const unsigned char* s = &data[p * static_cast<size_t>(channels)];
    unsigned char* d = &out.rgba[4 * p];
    const bool grey = channels <= 2;
    d[0] = s[0];
    d[1] = grey ? s[0] : s[1];
    d[2] = grey ? s[0] : s[2];
    d[3] = channels == 2 ? s[1] : (channels == 4 ? s[3] : 255);
  }
  return true;
#else
  why = "texture decoding needs a build with -DRAYCOH_IMAGE_IO=ON (OpenImageIO)";
  return false;
#endif
}

void check_output_image_path(const std::string& what, const std::string& path) {
  const std::string ext = extension_of(path);
  if (ext != ".pfm" && ext != ".exr" && ext != ".png")
    throw Error(what + " " + path + ": unknown image extension '" + ext + "'; valid: .exr, .png, .pfm");
  if (ext != ".pfm" && !image_io_available()) no_image_io(what + " " + path);
}

void write_image(const Image& image, const std::string& path, [[maybe_unused]] const ToneMap& tm) {
  check_output_image_path("image", path);
  const std::string ext = extension_of(path);
  if (image.empty()) throw Error(path + ": cannot write an empty image");
  std::error_code ec;
  if (std::filesystem::path(path).has_parent_path())
    std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
  if (ext == ".pfm") {
    write_pfm(image, path);
  } else {
#if RAYCOH_IMAGE_IO
    write_file_atomically(path, encode_oiio(image, path, ext == ".png", tm));
#endif
  }
}

std::string png_bytes([[maybe_unused]] const Image& image, [[maybe_unused]] const ToneMap& tm) {
#if RAYCOH_IMAGE_IO
  return encode_oiio(image, "image.png", true, tm);
#else
  throw Error("PNG output needs image I/O (this build has RAYCOH_IMAGE_IO=OFF)");
#endif
}

Image read_image(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw Error(path + ": no such image file");
  const std::string ext = extension_of(path);
  if (ext == ".pfm") return read_pfm(path);
  if (ext != ".exr") throw Error(path + ": cannot read '" + ext + "' images; valid: .exr, .pfm");
#if RAYCOH_IMAGE_IO
  return read_oiio(path);
#else
  no_image_io(path);
#endif
}

}  // namespace raycoh
