#include "oiio/exr_header.h"

#include <fstream>
#include <string>

#include "core/error.h"

namespace raycoh {

namespace {

constexpr uint32_t kMagic = 20000630;   // 76 2f 31 01
constexpr uint32_t kLongNames = 0x400;  // version flags
constexpr uint32_t kMultiPart = 0x1000;
constexpr int kMaxHeaders = 1024;  // parts of a multi-part file

class HeaderReader {
 public:
  explicit HeaderReader(const std::string& path) : path_(path), in_(path, std::ios::binary) {
    if (!in_) throw Error(path + ": cannot open");
    in_.seekg(0, std::ios::end);
    size_ = static_cast<int64_t>(in_.tellg());
    in_.seekg(0);
  }
  [[noreturn]] void fail(const std::string& why) const {
    throw Error(path_ + ": not a valid OpenEXR file (" + why + ")");
  }
  int64_t left() { return size_ - static_cast<int64_t>(in_.tellg()); }
  uint32_t u32() {
    unsigned char b[4];
    if (!in_.read(reinterpret_cast<char*>(b), 4)) fail("the header ends early");
    return b[0] | b[1] << 8 | b[2] << 16 | static_cast<uint32_t>(b[3]) << 24;
  }
  // A null-terminated name of at most `max` characters (empty: the end of a header).
  std::string name(size_t max) {
    std::string s;
    for (char c; in_.get(c) && c != '\0';)
      if (s.size() == max)
        fail("a name longer than " + std::to_string(max) + " characters");
      else
        s += c;
    if (!in_) fail("the header ends early");
    return s;
  }
  void skip(int64_t n) { in_.seekg(n, std::ios::cur); }

 private:
  std::string path_;
  std::ifstream in_;
  int64_t size_ = 0;
};

void check_window(HeaderReader& r, const ExrLimits& limits) {
  const auto xmin = static_cast<int32_t>(r.u32()), ymin = static_cast<int32_t>(r.u32());
  const auto xmax = static_cast<int32_t>(r.u32()), ymax = static_cast<int32_t>(r.u32());
  const int64_t w = int64_t{xmax} - xmin + 1, h = int64_t{ymax} - ymin + 1;
  if (w < 1 || h < 1 || w > limits.max_side || h > limits.max_side || w * h > limits.max_pixels)
    r.fail("data window " + std::to_string(w) + "x" + std::to_string(h) + "; valid: 1 to " +
           std::to_string(limits.max_pixels) + " pixels, at most " + std::to_string(limits.max_side) + " a side");
}

void check_tiles(HeaderReader& r, const ExrLimits& limits) {
  const int64_t tw = r.u32(), th = r.u32();
  r.skip(1);  // level and rounding mode
  // Each side first: the product of two 32-bit sides overflows int64 (found by fuzz_compare_image).
  if (tw < 1 || th < 1 || tw > limits.max_tile_pixels || th > limits.max_tile_pixels ||
      tw * th > limits.max_tile_pixels)
    r.fail("tiles of " + std::to_string(tw) + "x" + std::to_string(th) + "; valid: at most " +
           std::to_string(limits.max_tile_pixels) + " pixels");
}

// One header's attributes up to its terminating null byte; false when the header is empty (the end of a
// multi-part file's headers).
bool check_one_header(HeaderReader& r, size_t max_name, const ExrLimits& limits) {
  for (int count = 0;; ++count) {
    const std::string attribute = r.name(max_name);
    if (attribute.empty()) return count > 0;
    const std::string type = r.name(max_name);
    const auto size = static_cast<int32_t>(r.u32());
    if (size < 0 || size > r.left())
      r.fail("attribute '" + attribute + "' claims " + std::to_string(size) + " bytes, " + std::to_string(r.left()) +
             " are left");
    if (attribute == "dataWindow" && type == "box2i" && size == 16) {
      check_window(r, limits);
    } else if (attribute == "tiles" && type == "tiledesc" && size == 9) {
      check_tiles(r, limits);
    } else {
      r.skip(size);
    }
  }
}

}  // namespace

void check_exr_header(const std::string& path, const ExrLimits& limits) {
  HeaderReader r(path);
  if (r.u32() != kMagic) r.fail("no OpenEXR magic number");
  const uint32_t version = r.u32();
  const size_t max_name = (version & kLongNames) ? 255 : 31;
  if (!(version & kMultiPart)) {
    if (!check_one_header(r, max_name, limits)) r.fail("an empty header");
    return;
  }
  for (int part = 0; part < kMaxHeaders; ++part)
    if (!check_one_header(r, max_name, limits)) return;
  r.fail("more than " + std::to_string(kMaxHeaders) + " parts");
}

}  // namespace raycoh
