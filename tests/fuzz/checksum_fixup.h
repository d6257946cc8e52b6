// The fuzzer cannot compute a checksum, so without help every mutated reference file stops at its checksum test and
// the code behind it is never reached. These rewrite an input's checksums the way raycoh writes them (FNV-1a, as
// in shading/reference.cpp), so that a target can also feed the readers damaged files whose checksums agree: the
// case of a file written wrong rather than damaged afterwards.
#pragma once

#include <cstdint>
#include <string>

namespace raycoh::fuzz {

// 64-bit FNV-1a of bytes.
uint64_t fnv1a(const void* data, size_t n, uint64_t h = 1469598103934665603ull);
std::string hex16(uint64_t v);

// A reference cache sidecar (JSON object) with image_fnv1a, half_image_fnv1a and checksum recomputed for the given
// image bytes; `key_json`, when not empty, replaces its key. Input that is not a JSON object is returned unchanged.
std::string fix_sidecar(const std::string& sidecar, const std::string& image, const std::string& half,
                        const std::string& key_json);

// A reference part file with its "block <i> <hash> ..." lines and its "end <hash>" line recomputed from its header's
// size and the block bytes; unchanged where the header does not parse or the blocks would be large.
std::string fix_part(const std::string& part);

}  // namespace raycoh::fuzz
