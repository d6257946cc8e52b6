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
// spec; the generator (always noopt); and the renderer revision "r<kRendererVersion>/<git describe>".
// kRendererVersion is bumped by hand whenever the renderer's output changes, which the git revision alone does
// not catch while a tree is "-dirty".
#pragma once

#include <functional>
#include <string>

#include "bvh/bvh_build.h"
#include "core/params.h"
#include "shading/image.h"
#include "shading/path_tracer.h"

namespace raycoh {

constexpr int kRendererVersion = 1;

// "r<kRendererVersion>/<git describe --always --dirty>" of this build.
std::string renderer_revision();
// $RAYCOH_CACHE, else "results/cache".
std::string default_cache_dir();
// See the key above. Throws raycoh::Error when a scene file cannot be read.
std::string scene_fingerprint(const std::string& scene_spec);

struct ReferenceRequest {
  std::string scene_spec;   // as given to load_scene
  RenderSettings settings;  // size, seed, depths
  int frames = 512;         // [1, 1 << 20]
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

}  // namespace raycoh
