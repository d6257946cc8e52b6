// A memory estimate before a large run: a run that would not fit is refused with the estimate, instead of being
// killed by the OOM killer half-way (or ending in std::bad_alloc). The estimate counts the per-pixel buffers of
// the command (rays, hits, G-buffer, batches, keys, accumulators, images) from the sizes of their types; the
// scene and its BVH come on top and are reported when loaded.
#pragma once

#include <cstdint>
#include <string>

namespace raycoh {

// Bytes this process can still allocate: MemAvailable of /proc/meminfo, lowered by a cgroup v2 memory limit.
// $RAYCOH_MEMORY_AVAILABLE (bytes, or with a K/M/G suffix) replaces it, e.g. to test the refusal.
uint64_t available_memory_bytes();

// Per-pixel buffers of `table`/`sweep`/`validate` and of the rendering commands, in bytes.
uint64_t experiment_bytes(int width, int height);
uint64_t rendering_bytes(int width, int height);

// Throws raycoh::Error "<what>: needs about X GiB (...), Y GiB available; ..." when need > available.
void check_memory(const std::string& what, uint64_t need_bytes);

}  // namespace raycoh
