// Fuzz targets of the reference readers (shading/reference.cpp): a cache entry (sidecar JSON + image + half image)
// looked up by get_reference, and the part files of a sharded reference joined by combine_reference_parts.
#include <filesystem>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "scenes/scene.h"
#include "shading/reference.h"
#include "tests/fuzz/checksum_fixup.h"
#include "tests/fuzz/fuzz_targets.h"
#include "tests/fuzz/fuzz_util.h"

namespace raycoh::fuzz {

namespace {

// A reference of cornell small enough to render again in a millisecond when the entry is refused.
ReferenceRequest small_request() {
  ReferenceRequest r;
  r.scene_spec = "cornell";
  r.settings.width = 6;
  r.settings.height = 4;
  r.settings.max_depth = 2;
  r.frames = 2;
  r.frame_block = 1;
  r.revision = "fuzz";
  r.cache_dir = scratch_dir() + "/cache";
  return r;
}

}  // namespace

// First byte: bit 0 rewrites the sidecar's checksums to match (checksum_fixup.h), bit 1 also puts this request's
// key into it, so that the image readers behind those checks are reached. The rest: the sidecar, the image (.exr,
// or .pfm without image I/O) and the half image, split by fuzz_util.h's separator. The entry is then asked for
// (read when it passes, rendered again when not) and its frame count read as `quality --reference` reads it.
void fuzz_reference_cache(const uint8_t* data, size_t size) {
  if (size < 1) return;
  clear_scratch();
  const ReferenceRequest r = small_request();
  const std::string key = reference_key(r);
  const std::string stem = "cornell-" + hex16(fnv1a(key.c_str(), key.size() + 1));
  std::vector<std::string> parts = split_input(data + 1, size - 1, 3);
  parts.resize(3);
  const std::string ext = float_image_extension();
  if (data[0] & 1) parts[0] = fix_sidecar(parts[0], parts[1], parts[2], data[0] & 2 ? key : "");
  std::filesystem::create_directories(r.cache_dir);
  write_scratch("cache/" + stem + ".json", parts[0]);
  const std::string image = write_scratch("cache/" + stem + ext, parts[1]);
  write_scratch("cache/" + stem + "-half1" + ext, parts[2]);
  const SmallScene& s = small_scene();
  expect_clean(stem, [&] { get_reference(s.scene, s.bvh, r); });
  expect_clean(stem, [&] { reference_file_frames(image); });
}

// First byte: bit 0 rewrites the block and end checksums to match (checksum_fixup.h). The rest: one or two part
// files (split by fuzz_util.h's separator), combined into a cache entry; the first is also checked as a finished
// shard of the small request.
void fuzz_reference_parts(const uint8_t* data, size_t size) {
  if (size < 1) return;
  clear_scratch();
  std::vector<std::string> parts = split_input(data + 1, size - 1, 2), paths;
  for (size_t i = 0; i < parts.size(); ++i) {
    if (data[0] & 1) parts[i] = fix_part(parts[i]);
    paths.push_back(write_scratch("ref-" + std::to_string(i) + ".part", parts[i]));
  }
  expect_clean("", [&] { combine_reference_parts(paths, scratch_dir() + "/cache"); });
  expect_clean("ref-", [&] { reference_part_done(paths[0], small_request(), 0, 2); });
}

}  // namespace raycoh::fuzz
