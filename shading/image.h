// Float RGB images, frame accumulation, tone mapping, crops and image files.
//
// Image        linear RGB, three floats per pixel, row-major, y = 0 at the top (the pixel numbering of the
//              ray batches: p = y * width + x).
// Accumulator  per-pixel running sums over frames, in double so that a 4096-frame reference loses no
//              precision. A sample that is NaN or Inf in any channel is counted for its pixel and NOT added:
//              a non-finite value never reaches an accumulated image, and never silently (non_finite_samples()).
//              The mean divides by the pixel's count of finite samples.
// ToneMap      what turns linear radiance into a display image in [0, 1]:
//                exposure    float  default 1   (0, 1e6]: linear scale applied first
//                auto_exposure  bool  default false: resolved() replaces exposure by the "key value" rule of
//                            Reinhard et al. ("Photographic Tone Reproduction for Digital Images", SIGGRAPH
//                            2002): exposure = 0.18 / exp(mean of log luminance) over the pixels with luminance
//                            > 0 of a given image (black background does not count), so that dark interiors
//                            (Sibenik lit through its windows) and bright scenes both land at middle grey
//                kind        aces (default): the ACES filmic curve fitted by Narkowicz ("ACES Filmic Tone
//                            Mapping Curve", 2015), x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), per channel
//                            clamp: plain clamp to [0, 1]
//              then the sRGB OETF (IEC 61966-2-1) and a clamp to [0, 1]. Both curves are monotone
//              non-decreasing; NaN maps to 0, +Inf to 1. PNG files and the PSNR/SSIM metrics use this image.
// Files        .pfm (Portable Float Map, little endian, written and read here: always available),
//              .exr (32-bit float, zip) and .png (tone-mapped 8-bit sRGB) through the OpenImageIO adapter
//              oiio/image_codec.h when built with RAYCOH_IMAGE_IO=ON (the default). Without it, .exr and .png
//              are a raycoh::Error naming the option. image_io_available() and the texture decoder
//              decode_rgba8 are that adapter's, included here for this header's users.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/vec.h"
#include "oiio/image_codec.h"

namespace raycoh {

struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;  // 3 * width * height

  Image() = default;
  Image(int w, int h, Vec3 fill = Vec3(0.f));
  size_t pixels() const { return static_cast<size_t>(width) * static_cast<size_t>(height); }
  bool empty() const { return pixels() == 0; }
  size_t index(int x, int y) const { return static_cast<size_t>(y) * static_cast<size_t>(width) + x; }
  Vec3 at(size_t p) const { return {rgb[3 * p], rgb[3 * p + 1], rgb[3 * p + 2]}; }
  Vec3 at(int x, int y) const { return at(index(x, y)); }
  void set(size_t p, Vec3 v) {
    rgb[3 * p] = v.x;
    rgb[3 * p + 1] = v.y;
    rgb[3 * p + 2] = v.z;
  }
  void set(int x, int y, Vec3 v) { set(index(x, y), v); }
};

// Per-pixel sums of frame samples.
class Accumulator {
 public:
  Accumulator() = default;
  Accumulator(int width, int height);
  int width() const { return width_; }
  int height() const { return height_; }
  // Adds one sample to pixel p, or counts it as non-finite. Different pixels may be added from different
  // threads at the same time; one pixel must not.
  void add(size_t p, Vec3 value);
  // Adds every pixel of `other` (same size) as if its samples had been added here.
  void merge(const Accumulator& other);
  // Mean of the finite samples per pixel (0 where a pixel has none).
  Image mean() const;
  uint64_t non_finite_samples() const;
  uint32_t non_finite_samples(size_t p) const { return non_finite_[p]; }
  uint32_t samples(size_t p) const { return samples_[p]; }
  // Pixels with at least one non-finite sample.
  uint64_t pixels_with_non_finite() const;
  // The raw parts (reference frame shards store them): 3 sums per pixel, finite and non-finite sample counts.
  const std::vector<double>& sums() const { return sum_; }
  const std::vector<uint32_t>& sample_counts() const { return samples_; }
  const std::vector<uint32_t>& non_finite_counts() const { return non_finite_; }
  // The accumulator with these parts (sizes checked).
  static Accumulator from_parts(int width, int height, std::vector<double> sums, std::vector<uint32_t> samples,
                                std::vector<uint32_t> non_finite);

 private:
  int width_ = 0, height_ = 0;
  std::vector<double> sum_;           // 3 per pixel
  std::vector<uint32_t> samples_;     // finite samples added
  std::vector<uint32_t> non_finite_;  // samples rejected
};

enum class ToneMapKind { Aces, Clamp };

struct ToneMap {
  ToneMapKind kind = ToneMapKind::Aces;
  float exposure = 1.f;
  bool auto_exposure = false;
};

constexpr float kAutoExposureKey = 0.18f;
// exposure = kAutoExposureKey / log-average luminance of the pixels with luminance > 0 (1 if there are none).
float auto_exposure(const Image& image);
// tm with auto exposure replaced by the exposure it gives on `image`; tm itself when it has a fixed exposure.
ToneMap resolved(const ToneMap& tm, const Image& image);

// "aces" | "clamp"; throws raycoh::Error naming the valid choices.
ToneMapKind parse_tone_map(const std::string& name);
// One line for reports and CSV columns, e.g. "aces(Narkowicz 2015),exposure=1,srgb" ("exposure=auto" before
// resolving).
std::string describe(const ToneMap& tm);
float srgb_oetf(float linear);
// Display value in [0, 1] of one linear channel value.
float tone_map_channel(float linear, const ToneMap& tm);
Image tone_mapped(const Image& linear, const ToneMap& tm);

struct Crop {
  int x = 0, y = 0, w = 0, h = 0;
};
// "x,y,w,h"; throws raycoh::Error naming `what` (e.g. "--crop") on a malformed value.
Crop parse_crop(const std::string& what, const std::string& text);
// Throws raycoh::Error naming `what` unless the crop has a positive size and lies inside a width x height image.
void check_crop(const std::string& what, const Crop& c, int width, int height);
Image crop(const Image& image, const Crop& c);

// PFM (always available). pfm_bytes is the file's content; write_pfm writes it through write_image's path.
std::string pfm_bytes(const Image& image);
void write_pfm(const Image& image, const std::string& path);
Image read_pfm(const std::string& path);

// By extension: .pfm, .exr (float) and .png (tone-mapped with tm, 8-bit). The file is encoded in memory and written
// by write_file_atomically (core/durable_file.h): whole or not at all, synced, no temp file left behind. Throws
// raycoh::Error for a path it cannot write (extension, build) and WriteError when the write fails.
void write_image(const Image& image, const std::string& path, const ToneMap& tm = {});
// The bytes of a PNG file of the image (tone-mapped with tm, 8-bit); throws raycoh::Error in a build without image
// I/O. For pages that embed an image (raycoh report).
std::string png_bytes(const Image& image, const ToneMap& tm);
// .pfm and .exr (RGB or RGBA; alpha is dropped, a single channel is replicated).
Image read_image(const std::string& path);
// Throws raycoh::Error naming `what` (e.g. "--out") unless write_image can write `path` in this build (a known
// extension, and image I/O for .exr/.png): lets a command fail before it renders rather than after.
void check_output_image_path(const std::string& what, const std::string& path);
// The extension references and float images use in this build: ".exr" with image I/O, else ".pfm".
const char* float_image_extension();

}  // namespace raycoh
