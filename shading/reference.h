// Reference images: many frames of NoOpt, cached on disk and never reused when anything that decides the image
// differs (DESIGN.md section 5).
//
// A cache entry is two files in the cache folder (default $RAYCOH_CACHE, else results/cache):
//   <scene>-<digest>.exr (or .pfm in a build without image I/O)  the mean image, 32-bit float
//   <scene>-<digest>.json                                        the full key, written after the image
// digest = 64-bit FNV-1a of the key's canonical JSON. The sidecar also holds the FNV-1a of the image file's bytes
// (image_fnv1a) and a checksum of its own fields (checksum). An entry is reused only when the sidecar's key equals
// the requested key field for field, both checksums verify, and the image reads back with the key's size;
// otherwise the reference is rendered again (with a warning when the checksums fail) and both files are replaced
// (image first, then sidecar, each written whole and renamed). A lock on the entry ("<stem>.lock") lets one run
// render it while another asking for the same entry waits and then reads it.
//
// The key: scene spec; scene fingerprint (built-in scenes: their spec, since the code revision covers the
// generator; files: FNV-1a of the scene file's bytes plus name, size and modification time of every file beside
// it, which covers .bin buffers and .mtl files); width, height, frames, seed, max_depth, rr_depth; the tracer
// spec; the generator (always noopt); the frame block; and the renderer revision "r<kRendererVersion>/<git
// describe>". kRendererVersion is bumped by hand whenever the renderer's output changes, which the git revision
// alone does not catch while a tree is "-dirty" (2: frames are summed in blocks, below; 3: glTF punctual lights
// and per-texel alpha cut-outs).
//
// Frame blocks: frames 0 .. frames-1 are rendered in blocks of frame_block frames (the last one may be shorter);
// each block is summed on its own, in double, in frame order, and the reference's sums are the block sums added
// in block order (Accumulator::merge), then divided by the per-pixel sample counts. Because that order does not
// depend on who rendered a block, a reference rendered as frame shards of whole blocks (render_reference_part,
// one process each) and combined (combine_reference_parts) is the same image, bit for bit, as one process's.
// A part file holds one line of JSON (the entry's key and stem, the shard, its blocks), then per block the raw
// accumulator (3 doubles of sums, then a uint32 of finite and one of non-finite samples per pixel, native byte
// order), then a line "end <FNV-1a of the block bytes>".
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/params.h"
#include "shading/image.h"
#include "shading/path_tracer.h"

namespace raycoh {

constexpr int kRendererVersion = 3;
constexpr int kReferenceFrameBlock = 64;

// "r<kRendererVersion>/<git describe --always --dirty>" of this build.
std::string renderer_revision();
// $RAYCOH_CACHE, else "results/cache".
std::string default_cache_dir();
// See the key above. Throws raycoh::Error when a scene file cannot be read.
std::string scene_fingerprint(const std::string& scene_spec);

struct ReferenceRequest {
  std::string scene_spec;                  // as given to load_scene
  RenderSettings settings;                 // size, seed, depths
  int frames = 512;                        // [1, 1 << 20]
  int frame_block = kReferenceFrameBlock;  // [1, 1 << 20]; part of the key (tests use small blocks)
  PluginSpec tracer{"cpu", ""};
  std::string cache_dir;  // empty: default_cache_dir()
  std::string revision;   // empty: renderer_revision(); tests set it to check invalidation
  // Called after every rendered frame (done, total), e.g. for a progress bar; may be empty.
  std::function<void(int, int)> progress;
};

struct Reference {
  Image image;
  std::string path;  // the cached image file
  bool from_cache = false;
  double render_s = 0;      // 0 when read from the cache
  uint64_t non_finite = 0;  // NaN/Inf frame samples left out while rendering it
};

// Canonical JSON text of the request's key.
std::string reference_key(const ReferenceRequest& request);

// Returns the cached reference for the request, or renders it (NoOpt, frames 0 .. frames-1) with the given
// scene (already loaded from request.scene_spec) and its BVH, and stores it. Throws raycoh::Error on bad
// settings or when the cache cannot be written.
Reference get_reference(const Scene& scene, const Bvh& bvh, const ReferenceRequest& request);

// Frames [first, end) of shard `index` of `count` (0 <= index < count): contiguous, equal, whole blocks. Throws
// raycoh::Error ("--shard I/N ...") naming the valid shard counts when the shards would not be whole blocks.
struct FrameRange {
  int first = 0, end = 0;
};
FrameRange reference_shard_frames(int frames, int frame_block, int index, int count);

// Renders shard `index` of `count` of the request's reference and writes its part file to `path` (whole or not
// at all); returns the seconds it rendered. Throws raycoh::Error on bad settings or shards.
double render_reference_part(const Scene& scene, const Bvh& bvh, const ReferenceRequest& request, int index, int count,
                             const std::string& path);

// True when `path` is already a part file of this request's shard `index` of `count` (its header; combining checks
// its data), so that a resubmitted shard need not render again.
bool reference_part_done(const std::string& path, const ReferenceRequest& request, int index, int count);

// Reads the part files of one reference (any order), checks that they share the key and that every shard is
// there once, adds their blocks in frame order and stores the cache entry in cache_dir ("" = the default) as
// get_reference would have. Throws raycoh::Error naming the file and what is wrong.
Reference combine_reference_parts(const std::vector<std::string>& parts, const std::string& cache_dir);

}  // namespace raycoh
