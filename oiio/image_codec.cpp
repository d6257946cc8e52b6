// The one file that includes OpenImageIO (oiio/image_codec.h). OIIO bundles its own fmt and defines
// FMT_EXCEPTIONS 0 when its headers come first, so nothing of fmt is included here (the two would clash).
#include "oiio/image_codec.h"

#include <algorithm>
#include <cstring>
#include <memory>
#include <string>

#include "core/error.h"
#include "oiio/exr_header.h"

#if RAYCOH_IMAGE_IO
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#endif

namespace raycoh {

namespace {

#if RAYCOH_IMAGE_IO
// The file's bytes, encoded in memory (OIIO's IOVecOutput proxy); `path` only chooses the format.
std::string encode_oiio(const std::string& path, int width, int height, bool png, const void* data) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out || !out->supports("ioproxy")) throw Error(path + ": cannot write: " + OIIO::geterror());
  const OIIO::TypeDesc type = png ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT;
  OIIO::ImageSpec spec(width, height, 3, type);
  if (!png) spec.attribute("compression", "zip");
  std::vector<unsigned char> encoded;
  OIIO::Filesystem::IOVecOutput memory(encoded);
  OIIO::Filesystem::IOProxy* proxy = &memory;
  spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  if (!out->open(path, spec) || !out->write_image(type, data) || !out->close())
    throw Error(path + ": cannot encode the image: " + out->geterror());
  return std::string(encoded.begin(), encoded.end());
}

// An input opened with the reader of `format` only. OIIO's ImageInput::open hands a file its extension's reader
// cannot open to every other reader it has in turn (dozens, from DPX to RAW): a damaged or mislabelled file would
// be decoded as whatever format accepts it, slowly, by readers raycoh never means to use. Empty when the reader
// refuses the file; `why` then says why.
std::unique_ptr<OIIO::ImageInput> open_as(const char* format, const std::string& name, OIIO::Filesystem::IOProxy* proxy,
                                          std::string& why) {
  auto in = OIIO::ImageInput::create(format);
  if (!in) {
    why = OIIO::geterror();
    return nullptr;
  }
  if (proxy && !in->set_ioproxy(proxy)) {
    why = std::string("the ") + format + " reader cannot read from memory";
    return nullptr;
  }
  OIIO::ImageSpec spec;
  if (!in->open(name, spec)) {
    why = in->geterror();
    if (why.empty()) why = std::string("not a valid ") + format + " file";
    return nullptr;
  }
  return in;
}
// The float pixels of `in` (its first `channels` channels), read a strip of rows at a time (about 2^20 pixels, whole
// rows of tiles in a tiled file) into `data`, which grows as the strips decode: a damaged header claiming millions
// of pixels in a file of a few hundred bytes fails at its first strip, not after allocating and zeroing the whole
// claim (a 4.4 KB file claiming 8192 x 8192 pixels peaked at 919 MB). False when a strip cannot be read.
bool read_strips(OIIO::ImageInput& in, int channels, std::vector<float>& data) {
  const OIIO::ImageSpec& spec = in.spec();
  const size_t row = static_cast<size_t>(spec.width) * static_cast<size_t>(channels);
  const int unit = spec.tile_width > 0 ? std::max(1, spec.tile_height) : 1;
  const int rows = std::max(unit, std::max(1, (1 << 20) / spec.width) / unit * unit);
  data.clear();
  for (int y = 0; y < spec.height; y += rows) {
    const int n = std::min(rows, spec.height - y);
    data.resize(data.size() + row * static_cast<size_t>(n));
    float* strip = data.data() + row * static_cast<size_t>(y);
    const int y0 = spec.y + y;
    const bool ok = spec.tile_width > 0
                        ? in.read_tiles(0, 0, spec.x, spec.x + spec.width, y0, y0 + n, spec.z, spec.z + 1, 0, channels,
                                        OIIO::TypeDesc::FLOAT, strip)
                        : in.read_scanlines(0, 0, y0, y0 + n, spec.z, 0, channels, OIIO::TypeDesc::FLOAT, strip);
    if (!ok) return false;
  }
  return true;
}
#else
[[noreturn]] void no_image_io(const std::string& path) {
  throw Error(path + ": EXR and PNG need a build with -DRAYCOH_IMAGE_IO=ON (OpenImageIO)");
}
#endif

}  // namespace

bool image_io_available() { return RAYCOH_IMAGE_IO != 0; }

bool decode_rgba8([[maybe_unused]] const unsigned char* bytes, [[maybe_unused]] size_t size,
                  [[maybe_unused]] Rgba8Image& out, std::string& why) {
#if RAYCOH_IMAGE_IO
  // The format comes from the magic bytes: embedded images have no file name, and URIs may lie.
  const char* format = nullptr;
  if (size >= 8 && std::memcmp(bytes, "\x89PNG", 4) == 0) format = "png";
  if (size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8) format = "jpeg";
  if (size >= 12 && std::memcmp(bytes, "RIFF", 4) == 0 && std::memcmp(bytes + 8, "WEBP", 4) == 0) format = "webp";
  if (!format) {
    why = "not a PNG, JPEG or WebP image";
    return false;
  }
  OIIO::Filesystem::IOMemReader memory(bytes, size);
  auto in = open_as(format, std::string("texture.") + format, &memory, why);
  if (!in) return false;
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

std::string encode_exr(const std::string& path, [[maybe_unused]] int width, [[maybe_unused]] int height,
                       [[maybe_unused]] const float* rgb) {
#if RAYCOH_IMAGE_IO
  return encode_oiio(path, width, height, false, rgb);
#else
  no_image_io(path);
#endif
}

std::string encode_png(const std::string& path, [[maybe_unused]] int width, [[maybe_unused]] int height,
                       [[maybe_unused]] const unsigned char* rgb) {
#if RAYCOH_IMAGE_IO
  return encode_oiio(path, width, height, true, rgb);
#else
  no_image_io(path);
#endif
}

RgbFloatImage read_rgb_float(const std::string& path) {
#if RAYCOH_IMAGE_IO
  check_exr_header(path);  // before OpenEXR allocates what a damaged header claims
  std::string why;
  auto in = open_as("openexr", path, nullptr, why);
  if (!in) throw Error(path + ": cannot read it as an OpenEXR image: " + why);
  const OIIO::ImageSpec& spec = in->spec();
  // At most 2^26 pixels (8192 x 8192), 65536 a side, tiles of at most 2^22 pixels: a damaged header can claim any
  // size, and a compressed file's size does not bound its pixels.
  const ExrLimits limits;  // the header check's, applied again to what OpenImageIO read
  const double tile_pixels = static_cast<double>(spec.tile_width) * spec.tile_height;
  if (spec.width < 1 || spec.height < 1 || spec.width > limits.max_side || spec.height > limits.max_side ||
      spec.nchannels < 1 || spec.depth > 1 || static_cast<double>(spec.width) * spec.height > limits.max_pixels ||
      tile_pixels > limits.max_tile_pixels)
    throw Error(path + ": unsupported image (" + std::to_string(spec.width) + "x" + std::to_string(spec.height) + ", " +
                std::to_string(spec.nchannels) + " channels, " + std::to_string(spec.tile_width) + "x" +
                std::to_string(spec.tile_height) + " tiles; valid: 1 to " + std::to_string(limits.max_pixels) +
                " pixels, at most " + std::to_string(limits.max_side) + " a side, tiles of at most " +
                std::to_string(limits.max_tile_pixels) + " pixels, 1 or more channels)");
  const int channels = std::min(spec.nchannels, 3);
  std::vector<float> data;
  if (!read_strips(*in, channels, data)) throw Error(path + ": cannot read pixels: " + in->geterror());
  in->close();
  RgbFloatImage img;
  img.width = spec.width;
  img.height = spec.height;
  img.rgb.resize(3 * static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height));
  for (size_t p = 0; p < img.rgb.size() / 3; ++p) {
    const float* s = &data[p * channels];
    for (int c = 0; c < 3; ++c) img.rgb[3 * p + c] = s[channels >= 3 ? c : 0];
  }
  return img;
#else
  no_image_io(path);
#endif
}

}  // namespace raycoh
