// Images, accumulation with non-finite counting, tone mapping, crops and the PFM format (see image.h).
// PFM: "PF\n<width> <height>\n<scale>\n" then float32 RGB rows from the BOTTOM row up; a negative scale means
// little endian. "Pf" files (one channel) are read and replicated to RGB.
#include "shading/image.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <utility>

#include "core/durable_file.h"
#include "core/error.h"
#include "core/params.h"

namespace raycoh {

Image::Image(int w, int h, Vec3 fill) : width(w), height(h) {
  RAYCOH_CHECK(w >= 0 && h >= 0, fmt::format("image size {}x{}", w, h));
  rgb.resize(3 * pixels());
  for (size_t p = 0; p < pixels(); ++p) set(p, fill);
}

Accumulator::Accumulator(int width, int height) : width_(width), height_(height) {
  RAYCOH_CHECK(width > 0 && height > 0, fmt::format("accumulator size {}x{}", width, height));
  const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
  sum_.assign(3 * n, 0.0);
  samples_.assign(n, 0);
  non_finite_.assign(n, 0);
}

void Accumulator::add(size_t p, Vec3 value) {
  if (!is_finite(value)) {
    ++non_finite_[p];
    return;
  }
  sum_[3 * p] += value.x;
  sum_[3 * p + 1] += value.y;
  sum_[3 * p + 2] += value.z;
  ++samples_[p];
}

void Accumulator::merge(const Accumulator& other) {
  RAYCOH_CHECK(other.width_ == width_ && other.height_ == height_,
               fmt::format("merging a {}x{} accumulator into {}x{}", other.width_, other.height_, width_, height_));
  for (size_t i = 0; i < sum_.size(); ++i) sum_[i] += other.sum_[i];
  for (size_t p = 0; p < samples_.size(); ++p) {
    samples_[p] += other.samples_[p];
    non_finite_[p] += other.non_finite_[p];
  }
}

Accumulator Accumulator::from_parts(int width, int height, std::vector<double> sums, std::vector<uint32_t> samples,
                                    std::vector<uint32_t> non_finite) {
  Accumulator acc(width, height);
  RAYCOH_CHECK(sums.size() == acc.sum_.size() && samples.size() == acc.samples_.size() &&
                   non_finite.size() == acc.non_finite_.size(),
               fmt::format("accumulator parts of the wrong size for {}x{}", width, height));
  acc.sum_ = std::move(sums);
  acc.samples_ = std::move(samples);
  acc.non_finite_ = std::move(non_finite);
  return acc;
}

Image Accumulator::mean() const {
  Image img(width_, height_);
  for (size_t p = 0; p < samples_.size(); ++p) {
    if (samples_[p] == 0) continue;
    const double inv = 1.0 / samples_[p];
    img.set(p, Vec3{static_cast<float>(sum_[3 * p] * inv), static_cast<float>(sum_[3 * p + 1] * inv),
                    static_cast<float>(sum_[3 * p + 2] * inv)});
  }
  return img;
}

uint64_t Accumulator::non_finite_samples() const {
  uint64_t n = 0;
  for (uint32_t c : non_finite_) n += c;
  return n;
}

uint64_t Accumulator::pixels_with_non_finite() const {
  uint64_t n = 0;
  for (uint32_t c : non_finite_) n += c > 0;
  return n;
}

ToneMapKind parse_tone_map(const std::string& name) {
  if (name == "aces") return ToneMapKind::Aces;
  if (name == "clamp") return ToneMapKind::Clamp;
  throw Error(fmt::format("unknown tone map '{}'; valid: aces, clamp", name));
}

std::string describe(const ToneMap& tm) {
  return fmt::format("{},exposure={},srgb", tm.kind == ToneMapKind::Aces ? "aces(Narkowicz 2015)" : "clamp",
                     tm.auto_exposure ? std::string("auto") : fmt::format("{:.6g}", tm.exposure));
}

float auto_exposure(const Image& image) {
  double sum_log = 0;
  size_t n = 0;
  for (size_t p = 0; p < image.pixels(); ++p) {
    const Vec3 c = image.at(p);
    const double y = 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
    if (!(y > 0) || !std::isfinite(y)) continue;
    sum_log += std::log(y);
    ++n;
  }
  if (n == 0) return 1.f;
  const double e = kAutoExposureKey / std::exp(sum_log / static_cast<double>(n));
  return static_cast<float>(std::clamp(e, 1e-6, 1e6));
}

ToneMap resolved(const ToneMap& tm, const Image& image) {
  if (!tm.auto_exposure) return tm;
  ToneMap out = tm;
  out.auto_exposure = false;
  out.exposure = auto_exposure(image);
  return out;
}

float srgb_oetf(float linear) {
  if (!(linear > 0.f)) return 0.f;
  if (linear >= 1.f) return 1.f;
  return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.f / 2.4f) - 0.055f;
}

float tone_map_channel(float linear, const ToneMap& tm) {
  if (std::isnan(linear)) return 0.f;
  float x = linear * tm.exposure;
  if (!(x > 0.f)) return 0.f;
  if (tm.kind == ToneMapKind::Aces) {
    if (std::isinf(x)) return 1.f;
    x = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
  }
  return std::clamp(srgb_oetf(x), 0.f, 1.f);
}

Image tone_mapped(const Image& linear, const ToneMap& tm) {
  Image out = linear;
  for (float& v : out.rgb) v = tone_map_channel(v, tm);
  return out;
}

Crop parse_crop(const std::string& what, const std::string& text) {
  std::vector<int> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) v.push_back(parse_int(what, item, 0, 1 << 20));
  if (v.size() != 4) throw Error(fmt::format("{} '{}': expected x,y,w,h (four integers)", what, text));
  return {v[0], v[1], v[2], v[3]};
}

void check_crop(const std::string& what, const Crop& c, int width, int height) {
  if (c.w < 1 || c.h < 1)
    throw Error(fmt::format("{} {},{},{},{}: width and height must be at least 1", what, c.x, c.y, c.w, c.h));
  if (c.x < 0 || c.y < 0 || static_cast<int64_t>(c.x) + c.w > width || static_cast<int64_t>(c.y) + c.h > height)
    throw Error(fmt::format("{} {},{},{},{} is not inside the {}x{} image (need x + w <= {} and y + h <= {})", what,
                            c.x, c.y, c.w, c.h, width, height, width, height));
}

Image crop(const Image& image, const Crop& c) {
  check_crop("crop", c, image.width, image.height);
  Image out(c.w, c.h);
  for (int y = 0; y < c.h; ++y)
    for (int x = 0; x < c.w; ++x) out.set(x, y, image.at(c.x + x, c.y + y));
  return out;
}

std::string pfm_bytes(const Image& image) {
  std::string bytes = fmt::format("PF\n{} {}\n-1.0\n", image.width, image.height);
  static_assert(std::endian::native == std::endian::little, "PFM writer assumes a little-endian host");
  for (int y = image.height - 1; y >= 0; --y)
    bytes.append(reinterpret_cast<const char*>(&image.rgb[3 * image.index(0, y)]), 3 * sizeof(float) * image.width);
  return bytes;
}

void write_pfm(const Image& image, const std::string& path) { write_file_atomically(path, pfm_bytes(image)); }

Image read_pfm(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(fmt::format("{}: cannot open (missing file?)", path));
  std::string magic;
  long long w = 0, h = 0;
  double scale = 0;
  in >> magic >> w >> h >> scale;
  if (!in || (magic != "PF" && magic != "Pf"))
    throw Error(fmt::format("{}: not a PFM file (header must be PF or Pf, width, height, scale)", path));
  if (w < 1 || h < 1 || w > (1 << 16) || h > (1 << 16) || scale == 0.0 || !std::isfinite(scale))
    throw Error(fmt::format("{}: bad PFM header (size {}x{}, scale {})", path, w, h, scale));
  in.get();  // the single whitespace character that ends the header
  const int channels = magic == "PF" ? 3 : 1;
  // The pixel data must be in the file before a buffer of the header's size is allocated: a damaged header may
  // claim 65536 x 65536 pixels (48 GiB) in a file of a few bytes.
  const std::streamoff header = in.tellg();
  in.seekg(0, std::ios::end);
  const std::streamoff file_bytes = in.tellg();
  in.seekg(header);
  const uint64_t need = static_cast<uint64_t>(w * h * channels) * sizeof(float);
  if (header < 0 || file_bytes < header || static_cast<uint64_t>(file_bytes - header) < need)
    throw Error(fmt::format("{}: truncated PFM ({} of {} bytes of pixel data)", path,
                            header < 0 || file_bytes < header ? 0 : file_bytes - header, need));
  std::vector<float> data(static_cast<size_t>(w * h * channels));
  in.read(reinterpret_cast<char*>(data.data()), static_cast<std::streamsize>(data.size() * sizeof(float)));
  if (in.gcount() != static_cast<std::streamsize>(data.size() * sizeof(float)))
    throw Error(fmt::format("{}: truncated PFM ({} of {} bytes of pixel data)", path, in.gcount(),
                            data.size() * sizeof(float)));
  if (scale > 0) {  // big endian file on a little-endian host
    for (float& f : data) f = std::bit_cast<float>(__builtin_bswap32(std::bit_cast<uint32_t>(f)));
  }
  Image img(static_cast<int>(w), static_cast<int>(h));
  for (int y = 0; y < img.height; ++y) {
    const size_t row = static_cast<size_t>(img.height - 1 - y) * static_cast<size_t>(w) * channels;
    for (int x = 0; x < img.width; ++x) {
      const float* s = &data[row + static_cast<size_t>(x) * channels];
      img.set(x, y, channels == 3 ? Vec3{s[0], s[1], s[2]} : Vec3(s[0]));
    }
  }
  return img;
}

const char* float_image_extension() { return image_io_available() ? ".exr" : ".pfm"; }

}  // namespace raycoh
