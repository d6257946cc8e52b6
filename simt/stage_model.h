// The timing model of the device pipeline's stages around the trace (generation, keys, sort, gather) on a preset
// GPU: each kernel launch as a launch term plus the largest of its bytes over an effective streaming bandwidth, its
// instructions over the SMs' issue rate and (the generation kernels) its L1 wavefronts over the SMs' L1 pipelines
// (simt/stage_l1.h); CUB's onesweep sort as a per-pass floor plus each pass's bytes (or
// instructions). Modeled, never measured; docs/simt-model.md section 3 has the form, every constant's source and
// what is not modeled. Host only. The bytes each stage moves are simt/pipeline_model.h's.
//
// Kernels per stage, as cuda/ launches them (cuda/device_generators.cu, device_grouping.cu, device_keys.cu,
// device_stages.cu, CUB 3.0's DeviceRadixSort::SortPairs):
//   generation  tile_hits (a block of 128 threads per tile reads each pixel's hit flag), CUB's exclusive scan of
//               the tile counts (two kernels), and the generator's kernel (noopt or group: a block per tile).
//   keys        one key kernel, a thread per ray.
//   sort        CUB onesweep: a histogram kernel (reads the keys once), an exclusive-sum kernel, then per 8-bit
//               digit a memset of the look-back state and one onesweep pass (reads and writes keys and values).
//   permute     one gather kernel over every batch column.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "encoders/encoder.h"  // Encoder, KeyRecipe and KeyKind
#include "generators/generator.h"
#include "simt/gpu_model.h"
#include "simt/pipeline_model.h"
#include "simt/stage_l1.h"
#include "simt/stage_latency.h"
#include "simt/stage_paths.h"

namespace raycoh {

// What one secondary pass runs: the image, the generator's kernel and tiles, the reordering.
struct StageWork {
  int width = 0, height = 0;
  size_t rays = 0;
  bool grouping = false;  // ours / contiguous (the group kernel), else noopt
  int tile_w = 8, tile_h = 8;
  KeyKind key = KeyKind::None;
  int key_bits = 0;                           // 0: no reordering
  int window = 0;                             // > 0: the windowed reordering (one binning kernel)
  bool physical = true;                       // the gather runs (permute physical)
  GBufferRead gbuffer = GBufferRead::Wide64;  // the generation kernels' G-buffer read (Fields60: before 63b5750)
  GroupPath group_path;  // the group kernel's path (k > 0: its trip-counted count, simt/stage_paths.h)
  KeyWalks mlhcc_walks;  // MLHCC's cut walks per warp (> 0: its trip-counted count)
  NooptPath noopt_path;  // the noopt kernel's path (known: its per-path count)
  bool latency = false;  // the latency term of the generator and key kernels (simt/stage_latency.h)
  size_t pixels() const { return size_t(width) * size_t(height); }
};

// The pass a generator and an encoder make on a width x height image: the generator's device recipe (noopt, or the
// group kernel with its tiles; a generator without a GPU version is priced as noopt on 8x8 tiles) and the
// encoder's key kind and bits. `stats` (optional): the pass's group counts, for the group kernel's path.
StageWork stage_work(const Generator& generator, const Encoder& encoder, bool physical, int width, int height,
                     size_t rays, const GenerationStats* stats = nullptr);

// The constants of the form, the same for every preset (docs/simt-model.md section 3 gives each one's source).
constexpr double kStreamFraction = 0.9;             // effective streaming bandwidth / the preset's DRAM figure
constexpr double kLaunchCycles = 5000;              // per kernel launch, SM cycles
constexpr double kOnesweepPassFloorCycles = 21514;  // per onesweep pass (its memset and kernel), SM cycles

// The terms (milliseconds on `gpu`).
double stage_launch_ms(const GpuModelConfig& gpu);
double stage_stream_ms(const GpuModelConfig& gpu, double bytes);
// `warps` warps each occupying an SM partition `cycles` cycles, spread over every partition of the GPU.
double stage_issue_ms(const GpuModelConfig& gpu, double warps, double cycles);
// One launch: launch term + max(bytes term, instruction term, L1 term of `l1_wavefronts` per warp).
double stage_kernel_ms(const GpuModelConfig& gpu, double bytes, double warps, double cycles, double l1_wavefronts = 0);

// The terms of one kernel (milliseconds; the L1 term from its mean wavefronts per warp, simt/stage_l1.h; the
// latency term, simt/stage_latency.h, 0 unless StageWork::latency).
struct StageKernelTerms {
  double warps = 0, dram_ms = 0, issue_ms = 0, l1_ms = 0, l1_wavefronts = 0, latency_ms = 0;
  // What the terms were made of: partition cycles per warp (the issue term's count), the bytes it moves, and with
  // the latency term the
  // resident warps per SM and one block's dependent chain (SM cycles; noopt: every piece of its tile in turn).
  double cycles = 0, bytes = 0, resident_warps = 0, chain_cycles = 0;  // bytes: the bytes term's traffic
  double ms(const GpuModelConfig& gpu) const;                          // launch + the largest term
};
// The generation stage's generator kernel (noopt or group) and tile_hits kernel of pass w.
StageKernelTerms stage_generator_terms(const GpuModelConfig& gpu, const StageWork& w);
StageKernelTerms stage_tile_hits_terms(const GpuModelConfig& gpu, const StageWork& w);
// The key kernel of pass w (its L1 term 0).
StageKernelTerms stage_key_terms(const GpuModelConfig& gpu, const StageWork& w);

double stage_generation_ms(const GpuModelConfig& gpu, const StageWork& w);
double stage_key_ms(const GpuModelConfig& gpu, const StageWork& w);
double stage_sort_ms(const GpuModelConfig& gpu, size_t n, int key_bits);
double stage_permute_ms(const GpuModelConfig& gpu, double permute_bytes, size_t n);
// The gather kernel's terms (no L1 or latency term).
StageKernelTerms stage_permute_terms(const GpuModelConfig& gpu, double permute_bytes, size_t n);

// The stage kernels' costs per architecture (simt/stage_model.cpp has their sources), for the presets.
StageKernelCosts stage_costs_sm90();
StageKernelCosts stage_costs_sm86();

// Every stage of one pass: times by the model above, bytes by stage_traffic (simt/pipeline_model.h). `order`: the
// sorted indices (a physical permutation's gather reads through them).
ModeledStages stage_model(const GpuModelConfig& gpu, const StageWork& w, const std::vector<uint32_t>& order);

}  // namespace raycoh
