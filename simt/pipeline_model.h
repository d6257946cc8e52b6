// The bytes the rest of a frame's GPU pipeline moves: secondary-ray generation, key computation, radix sort and
// permutation. simt/stage_model.h prices them (with launches and instructions) on a preset GPU; a measured device
// pass sets its stage times beside them (the traffic bound). Modeled, not measured, and reported beside, never
// mixed with, measured stage times; the trace itself is timed by simt/timed_replay.h. Host only.
//
// What each stage moves (bytes per element; sources beside each function in pipeline_model.cpp):
//   generation  reads a G-buffer point per pixel, writes the ray batch (ray, pixel, pdf, weight, normal,
//               material) per ray. The same for every generator: `ours` exchanges directions in shared memory
//               (the paper, section 4), which costs no DRAM traffic.
//   keys        reads each ray, writes its key and index.
//   sort        CUB's onesweep LSD radix sort (Adinets & Merrill, "Onesweep: A Faster Least Significant Digit
//               Radix Sort for GPUs", 2022): one histogram pass reading the keys, then one pass per 8-bit digit
//               reading and writing keys and indices.
//   permute     a gather of every batch array through the order: each warp of 32 outputs reads the distinct
//               32-byte sectors its sources touch (counted exactly from the order; no reuse across warps, so an
//               upper bound) and writes its outputs contiguously.
// Not counted: caches between stages (every stage reads its input from DRAM).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "simt/gpu_model.h"

namespace raycoh {

// Each stage's modeled time (simt/stage_model.h) and the DRAM bytes it is modeled to move: the bytes are also the
// traffic bound a measured stage is set beside (scripts/gpu-check's stage table divides them by the copy bandwidth
// measured on the GPU).
struct ModeledStages {
  double gen_ms = 0, key_ms = 0, sort_ms = 0, permute_ms = 0;
  double gen_bytes = 0, key_bytes = 0, sort_bytes = 0, permute_bytes = 0;
  double reorder_ms() const { return key_ms + sort_ms + permute_ms; }
};

// Bytes one ray of a batch occupies on the device (the RayBatch arrays a trace and shading need).
size_t batch_bytes_per_ray();

// The bytes each stage moves.
double generation_bytes(size_t pixels, size_t rays);
double key_bytes(size_t rays, int key_bits);
double sort_bytes(size_t n, int key_bits);
// `order[i]` is the source of output i.
double permute_bytes(const uint32_t* order, size_t n);
// The windowed reordering (encoders/window.cpp) as one kernel: each block reads a window of rays, bins them on
// chip (shared memory) and writes them back in bin order, so the batch is read and written once, contiguously
// (physical mode), or the rays are read and the window-local order written (indirect mode). Its key, sort and
// permutation are all in this one figure. An assumption of ours, an upper bound of a hardware unit's cost.
double window_bytes(size_t n, bool physical);
// The generation stage of a noopt pass on 8x8 tiles over `pixels` pixels (simt/stage_model.h), for callers that
// know no more of the generator (harness/image/gpu_clock.h).
double modeled_generation_ms(const GpuModelConfig& gpu, size_t pixels, size_t rays);

// Each stage's bytes (the *_ms fields 0; simt/stage_model.h's stage_model adds the times): what a pass moves. A
// fused pass (generation and trace in one kernel, no batch) moves the G-buffer only.
ModeledStages stage_traffic(size_t pixels, int key_bits, int window, bool physical, size_t rays,
                            const std::vector<uint32_t>& order, bool fused = false);

}  // namespace raycoh
