// A check of an OpenEXR file's header before OpenEXR reads it (oiio/image_codec.cpp read_rgb_float). Debian's
// OpenEXR 3.1 allocates what a header claims before reading it: an 84-byte file whose string attribute claims
// 822 MB peaked at 934 MB (fuzz_compare_image; claiming 2 GB instead, 2.2 GB and 2.4 s), and a data window claims any
// number of scan lines, whose offset table is allocated at open. This walks the header's attributes (name, type, size,
// value: the OpenEXR file layout) without allocating and refuses, with one line naming the file, an attribute
// larger than the bytes left in the file, a header that does not end, and a data window or tile size beyond what
// raycoh reads (ExrLimits).
#pragma once

#include <cstdint>
#include <string>

namespace raycoh {

struct ExrLimits {
  int64_t max_side = 65536;        // pixels a side
  int64_t max_pixels = 1LL << 26;  // pixels in all (8192 x 8192)
  int64_t max_tile_pixels = 1LL << 22;
};

// Throws raycoh::Error (one line, naming `path`) when the header of the EXR file at `path` is damaged or claims
// more than `limits`; returns quietly for a header OpenEXR may read. Files that are not EXR at all (bad magic
// number) are refused too.
void check_exr_header(const std::string& path, const ExrLimits& limits = {});

}  // namespace raycoh
