// The EXR header check that runs before OpenEXR reads a file (oiio/exr_header.h): damaged or oversized headers
// are refused with one line naming the file, without allocating what they claim.
#include "oiio/exr_header.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "core/error.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

namespace fs = std::filesystem;
using test::error_of;

const fs::path kTiled = fs::path(RAYCOH_SOURCE_DIR) / "tests" / "data" / "tiled-70x40.exr";

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void put_u32(std::string& s, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) s[at + i] = static_cast<char>(v >> (8 * i));
}

// The offset of the value of attribute `name` (after its name, type and size), or npos.
size_t value_of(const std::string& s, const std::string& name) {
  const size_t at = s.find(name + '\0');
  if (at == std::string::npos) return at;
  const size_t type_end = s.find('\0', at + name.size() + 1);
  return type_end + 1 + 4;
}

// Checks a patched copy of the tiled fixture; returns the error ("no error" when accepted).
std::string check_patched(const std::string& bytes, const std::string& name) {
  const fs::path p = test::temp_dir("exr-header") / name;
  test::write_file(p, bytes);
  return error_of([&] { check_exr_header(p.string()); });
}

TEST(ExrHeader, AcceptsAValidTiledFile) {
  EXPECT_EQ(error_of([&] { check_exr_header(kTiled.string()); }), "no error");
}

TEST(ExrHeader, RefusesAnAttributeLargerThanTheFile) {
  std::string s = bytes_of(kTiled);
  const size_t v = value_of(s, "channels");
  ASSERT_NE(v, std::string::npos);
  put_u32(s, v - 4, 822738963);
  const std::string e = check_patched(s, "huge-attribute.exr");
  EXPECT_NE(e.find("huge-attribute.exr: not a valid OpenEXR file (attribute 'channels' claims 822738963 bytes"),
            std::string::npos)
      << e;
  put_u32(s, v - 4, 0x80000000u);  // negative
  EXPECT_NE(check_patched(s, "negative.exr").find("claims -2147483648 bytes"), std::string::npos);
}

TEST(ExrHeader, RefusesDataWindowsAndTilesBeyondTheLimits) {
  const std::string good = bytes_of(kTiled);
  std::string s = good;
  const size_t w = value_of(s, "dataWindow");
  ASSERT_NE(w, std::string::npos);
  put_u32(s, w + 8, 70000);  // xmax: 70000 - 5 + 1 wide
  EXPECT_NE(check_patched(s, "wide.exr").find("data window 69996x40; valid: 1 to 67108864 pixels, at most 65536"),
            std::string::npos);
  s = good;
  put_u32(s, w + 8, 8000);  // 7996 x 8000: 63.97 M pixels, within the limits
  put_u32(s, w + 12, 8002);
  EXPECT_EQ(check_patched(s, "big.exr"), "no error");
  put_u32(s, w + 8, 9000);  // 8996 x 8000: over 2^26
  EXPECT_NE(check_patched(s, "bigger.exr").find("data window 8996x8000"), std::string::npos);
  s = good;
  put_u32(s, w + 8, 1);  // xmax < xmin
  EXPECT_NE(check_patched(s, "empty.exr").find("data window -3x40"), std::string::npos);
  s = good;
  const size_t t = value_of(s, "tiles");
  ASSERT_NE(t, std::string::npos);
  put_u32(s, t, 4096);
  put_u32(s, t + 4, 4096);
  EXPECT_NE(check_patched(s, "tiles.exr").find("tiles of 4096x4096; valid: at most 4194304 pixels"), std::string::npos);
  put_u32(s, t, 3806520034u);  // sides whose product overflows int64 (fuzz_compare_image)
  put_u32(s, t + 4, 3806520034u);
  EXPECT_NE(check_patched(s, "tiles2.exr").find("tiles of 3806520034x3806520034"), std::string::npos);
}

TEST(ExrHeader, RefusesTruncatedAndForeignFiles) {
  const std::string good = bytes_of(kTiled);
  EXPECT_NE(check_patched(good.substr(0, 20), "cut.exr").find("cut.exr: not a valid OpenEXR file (the header ends"),
            std::string::npos);  // in the first attribute's type name
  EXPECT_NE(check_patched(good.substr(0, 40), "cut2.exr").find("attribute 'capDate' claims 19 bytes, 13 are left"),
            std::string::npos);
  EXPECT_NE(check_patched("PF\n4 4\n-1.0\n", "pfm.exr").find("no OpenEXR magic number"), std::string::npos);
  std::string s = good;
  s.replace(8, 8, std::string(40, 'a'));  // "capDate" (the first attribute) becomes a 40-character name
  EXPECT_NE(check_patched(s, "long.exr").find("a name longer than 31 characters"), std::string::npos);
  const std::string e = error_of([] { check_exr_header("/nonexistent/x.exr"); });
  EXPECT_NE(e.find("/nonexistent/x.exr: cannot open"), std::string::npos) << e;
}

}  // namespace
}  // namespace raycoh
