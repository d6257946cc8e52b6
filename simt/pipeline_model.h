// The rest of a frame's GPU pipeline on the `simt` tracer's modelled GPU: secondary-ray generation, key
// computation, radix sort and permutation, each as the DRAM traffic of a streaming kernel over the preset's
// bandwidth. Modeled, not measured, and reported beside, never mixed with, the measured CPU stage times; the
// trace itself is timed by simt/timed_replay.h. Host only.
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
// Not modelled: kernel launch overhead (a few microseconds per launch, negligible at 1080p), caches between
// stages, and the arithmetic of generation (sampling) and of MLHCC's cut lookups.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "simt/gpu_model.h"

namespace raycoh {

// Each stage's modeled time and the DRAM bytes it is modeled to move (time = bytes / the preset's bandwidth): the
// bytes are the traffic bound a measured stage is set beside (scripts/gpu-check's stage table divides them by the
// copy bandwidth measured on the GPU).
struct ModeledStages {
  double gen_ms = 0, key_ms = 0, sort_ms = 0, permute_ms = 0;
  double gen_bytes = 0, key_bytes = 0, sort_bytes = 0, permute_bytes = 0;
  double reorder_ms() const { return key_ms + sort_ms + permute_ms; }
};

// Bytes one ray of a batch occupies on the device (the RayBatch arrays a trace and shading need).
size_t batch_bytes_per_ray();

// Milliseconds to move `bytes` at the preset's DRAM bandwidth.
double modeled_stream_ms(const GpuModelConfig& gpu, double bytes);
// The bytes each stage moves; *_ms = modeled_stream_ms of them.
double generation_bytes(size_t pixels, size_t rays);
double key_bytes(size_t rays, int key_bits);
double sort_bytes(size_t n, int key_bits);
// `order[i]` is the source of output i.
double permute_bytes(const uint32_t* order, size_t n);
double modeled_generation_ms(const GpuModelConfig& gpu, size_t pixels, size_t rays);
double modeled_key_ms(const GpuModelConfig& gpu, size_t rays, int key_bits);
double modeled_sort_ms(const GpuModelConfig& gpu, size_t n, int key_bits);
double modeled_permute_ms(const GpuModelConfig& gpu, const uint32_t* order, size_t n);
// The windowed reordering (encoders/window.cpp) as one kernel: each block reads a window of rays, bins them on
// chip (shared memory) and writes them back in bin order, so the batch is read and written once, contiguously
// (physical mode), or the rays are read and the window-local order written (indirect mode). Its key, sort and
// permutation are all in this one figure. An assumption of ours, an upper bound of a hardware unit's cost.
double modeled_window_ms(const GpuModelConfig& gpu, size_t n, bool physical);

// The stages around the trace of one secondary batch of `rays` rays made from `pixels` pixels, modeled on `gpu`:
// generation, and for a reordering (key_bits > 0) its keys, sort and (physical) permutation by `order` (the sorted
// indices). A windowed reordering (window > 0) is one on-chip binning kernel: no key, sort or permutation pass.
// Indirect mode has no permutation kernel; the modeled trace then reads the rays in sorted order as if gathered
// (docs/simt-model.md, section 3).
ModeledStages modeled_stages(const GpuModelConfig& gpu, size_t pixels, int key_bits, int window, bool physical,
                             size_t rays, const std::vector<uint32_t>& order);
// The same stages' bytes alone (the *_ms fields 0): what a measured device pass moved, for its traffic bound. A
// fused pass (generation and trace in one kernel, no batch) moves the G-buffer only.
ModeledStages stage_traffic(size_t pixels, int key_bits, int window, bool physical, size_t rays,
                            const std::vector<uint32_t>& order, bool fused = false);

}  // namespace raycoh
