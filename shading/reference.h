// Reference images: many frames of NoOpt, cached on disk and never reused when anything that decides the image
// differs (docs/design.md section 5).
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
// spec; the generator (always noopt); the frame block; the device when it is not the CPU; and the renderer revision
// "r<kRendererVersion>/<git describe>". kRendererVersion is bumped by hand whenever the renderer's output changes,
// which the git revision alone does not catch while a tree is "-dirty" (2: frames are summed in blocks, below; 3: glTF
// punctual lights and per-texel alpha cut-outs; 4: textures' sRGB decode by core/srgb_decode.h instead of powf).
//
// Frame blocks: frames 0 .. frames-1 are rendered in blocks of frame_block frames (the last one may be shorter);
// each block is summed on its own, in double, in frame order, and the reference's sums are the block sums added
// in block order (Accumulator::merge), then divided by the per-pixel sample counts. Because that order does not
// depend on who rendered a block, a reference rendered as frame shards of whole blocks (render_reference_part,
// one process each) and combined (combine_reference_parts) is the same image, bit for bit, as one process's.
// A part file holds one line of JSON (format 2, the entry's key and stem, the shard, its blocks), then per block the
// raw accumulator (3 doubles of sums, then a uint32 of finite and one of non-finite samples per pixel, native byte
// order) and a line "block <index> <FNV-1a of the block's bytes> <render seconds> <host>", then a line "end <FNV-1a
// of all block bytes>". It is written as <part>.partial, each block synced when done, and moved into place when
// whole: a shard stopped midway keeps its verified blocks and renders only the rest when run again. Format 1
// (revision 4919fdd and before: no block lines, so no render time) is still read and combined.
//
// Device: a reference rendered by the device path tracer (device "cuda") estimates the same image as the CPU's, but
// its frames are other samples (statistically equal, not bit-equal), so its key holds the field "device": "cuda"
// (a CPU key has no such field, so CPU entries keep their digests): it has a cache entry of its own, no CPU run
// reads a GPU-made reference from the cache, and a GPU run never reads a CPU-made one. Part files carry the key, so
// shards of the two cannot be combined. A GPU reference can still serve a CPU run explicitly (quality --reference
// FILE), as any image can.
//
// Half reference: when the frames are two equal halves of whole blocks (frames a multiple of 2 * frame_block),
// the entry also holds the mean of the first half's blocks, "<stem>-half1<ext>" beside the image (half_path; its
// name and FNV-1a are in the sidecar as half_image, half_image_fnv1a). The second half is 2 * full - first, and
// the two halves are independent, which is what shading/metrics.h reference_noise needs. get_reference and
// combine_reference_parts write it (part files of either format need no change: they hold every block); an entry
// without it (from before, or frames that do not halve) is still used, without a noise estimate.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/params.h"
#include "shading/image.h"
#include "shading/path_tracer.h"

namespace raycoh {

constexpr int kRendererVersion = 4;
constexpr int kReferenceFrameBlock = 64;

// "r<kRendererVersion>/<git describe --always --dirty>" of this build.
std::string renderer_revision();
// $RAYCOH_CACHE, else "results/cache".
std::string default_cache_dir();
// See the key above. Throws raycoh::Error when a scene file cannot be read.
std::string scene_fingerprint(const std::string& scene_spec);

// One frame of a reference rendered into an accumulator by a path tracer other than the CPU's (the device path
// tracer of --device cuda, harness/image/render_device.h): the same frames and blocks, added the same way.
using FrameRenderer = std::function<void(uint32_t frame, Accumulator& acc)>;

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
  // The path tracer: "cpu" (the CPU's, with `tracer`) or another device's ("cuda"), whose frames make_renderer
  // renders (required then; called only when frames are rendered). See "Device" above.
  std::string device = "cpu";
  std::function<FrameRenderer()> make_renderer;
};

struct Reference {
  Image image;
  std::string path;  // the cached image file
  bool from_cache = false;
  double render_s = 0;                    // 0 when read from the cache; combined: the parts' render seconds summed
  std::vector<std::string> render_hosts;  // where it was rendered (combined: every part's hosts)
  uint64_t non_finite = 0;                // NaN/Inf frame samples left out while rendering it
  Image first_half;                       // empty when the entry has none (see "Half reference")
};

// "<dir>/<stem>-half1<ext>" for "<dir>/<stem><ext>": where the first-half mean of a reference image is looked for
// (cache entries, and quality's --reference FILE).
std::string half_reference_path(const std::string& image_path);
// The frame count of a reference image file, from the cache sidecar "<dir>/<stem>.json" beside it (a cache entry,
// or one written by reference-combine) when that sidecar names this image; 0 when there is none (unknown).
int reference_file_frames(const std::string& image_path);
// True when a reference of `frames` frames in blocks of frame_block has a half reference.
bool reference_halves(int frames, int frame_block);

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

// Renders shard `index` of `count` of the request's reference and writes its part file to `path` (moved there
// whole from `path`.partial); returns the seconds it rendered. The verified blocks of a `path`.partial that an
// earlier run of the same shard left are kept (replace = true: rendered again). Throws raycoh::Error on bad
// settings or shards, or when `path`.partial is another reference's (unless replace).
double render_reference_part(const Scene& scene, const Bvh& bvh, const ReferenceRequest& request, int index, int count,
                             const std::string& path, bool replace = false);

// True when `path` is already a part file of this request's shard `index` of `count` (its header; combining checks
// its data), so that a resubmitted shard need not render again.
bool reference_part_done(const std::string& path, const ReferenceRequest& request, int index, int count);

// Reads the part files of one reference (any order), checks that they share the key and that every shard is
// there once, adds their blocks in frame order and stores the cache entry in cache_dir ("" = the default) as
// get_reference would have; its sidecar's render_seconds and render_hosts are the parts' (summed; format-1 parts
// recorded none and are counted in parts_without_render_time). Throws raycoh::Error naming the file and what is
// wrong.
Reference combine_reference_parts(const std::vector<std::string>& parts, const std::string& cache_dir);

}  // namespace raycoh
