// The stage model's terms and its kernels per stage; see stage_model.h and docs/simt-model.md section 3.
#include "simt/stage_model.h"

#include <algorithm>
#include <cmath>

#include "core/ray_batch.h"
#include "core/shading_point.h"
#include "generators/grouping_block.h"  // tile_groups_bytes

namespace raycoh {
namespace {

constexpr double kWarp = 32;
constexpr double kSectorBytes = 32;
constexpr double kTileHitsThreads = 128;  // cuda/device_generators.cu, tile_hits_kernel's block
constexpr double kKeyThreads = 256;       // cuda/device_keys.cu kBlock, key_kernel's block
constexpr double kNooptPiece = 256;       // noopt_kernel's block: a tile of more than 256 pixels in pieces of 256

double div_up(double a, double b) { return std::ceil(a / b); }

double cycles_ms(const GpuModelConfig& gpu, double cycles) { return cycles / (gpu.gpu.clock_mhz * 1e3); }

// CUB's exclusive scan of the tile counts (DeviceScan: an init kernel and a single-pass scan kernel), `items`
// 4-byte words read and written.
double scan_ms(const GpuModelConfig& gpu, double items) {
  return stage_launch_ms(gpu) + stage_kernel_ms(gpu, 8.0 * items, 0, 0);
}

}  // namespace

StageWork stage_work(const Generator& generator, const Encoder& encoder, bool physical, int width, int height,
                     size_t rays, const GenerationStats* stats) {
  StageWork w;
  w.width = width;
  w.height = height;
  w.rays = rays;
  const DeviceRecipe r = generator.device_recipe();
  w.grouping = r.kind == DeviceRecipe::Kind::Grouping;
  if (r.kind != DeviceRecipe::Kind::None) {
    w.tile_w = r.tile_w;
    w.tile_h = r.tile_h;
  }
  // The per-pixel kernels (noopt, sadeghi, microjitter) run scanline order as one-row tiles (device_generators.cu).
  const bool per_pixel = r.kind == DeviceRecipe::Kind::NoOpt || r.kind == DeviceRecipe::Kind::SharedSample;
  if (per_pixel && r.order == RayOrder::Scanline) {
    w.tile_w = width;
    w.tile_h = 1;
  }
  w.key_bits = encoder.key_bits();
  w.window = encoder.window();
  w.key = encoder.recipe().kind;
  w.physical = physical;
  if (w.grouping) {
    w.group_path.k = static_cast<int>(r.grouping.k);
    w.group_path.rotate = r.grouping.reuse_frame == ReuseFrame::Rotate;
    w.group_path.hybrid_glossy = r.grouping.hybrid == HybridRule::Glossy;
    w.group_path.hybrid_own = r.grouping.hybrid == HybridRule::Independent;
    if (stats) {
      const auto n = [&](GroupType t) { return double(stats->groups[static_cast<int>(t)]); };
      w.group_path.nondiffuse_groups = n(GroupType::Glossy) + n(GroupType::Hybrid) + n(GroupType::Independent);
      w.group_path.hybrid_groups = n(GroupType::Hybrid);
    }
  }
  return w;
}

double stage_launch_ms(const GpuModelConfig& gpu) { return cycles_ms(gpu, kLaunchCycles); }

double stage_stream_ms(const GpuModelConfig& gpu, double bytes) {
  return bytes / (kStreamFraction * gpu.gpu.dram_gb_s * 1e6);
}

double stage_issue_ms(const GpuModelConfig& gpu, double warps, double cycles) {
  const double partitions = double(gpu.cache.sms) * gpu.gpu.schedulers_per_sm;
  return cycles_ms(gpu, warps * cycles / partitions);
}

double stage_kernel_ms(const GpuModelConfig& gpu, double bytes, double warps, double cycles, double l1_wavefronts) {
  return stage_launch_ms(gpu) + std::max({stage_stream_ms(gpu, bytes), stage_issue_ms(gpu, warps, cycles),
                                          stage_l1_ms(gpu, warps, l1_wavefronts)});
}

double StageKernelTerms::ms(const GpuModelConfig& gpu) const {
  return stage_launch_ms(gpu) + std::max({dram_ms, issue_ms, l1_ms, latency_ms});
}

namespace {

StageKernelTerms kernel_terms(const GpuModelConfig& gpu, double bytes, double warps, double cycles,
                              double l1_wavefronts) {
  StageKernelTerms t;
  t.warps = warps;
  t.cycles = cycles;
  t.bytes = bytes;
  t.dram_ms = stage_stream_ms(gpu, bytes);
  t.issue_ms = stage_issue_ms(gpu, warps, cycles);
  t.l1_wavefronts = l1_wavefronts;
  t.l1_ms = stage_l1_ms(gpu, warps, l1_wavefronts);
  return t;
}

double tiles_of(const StageWork& w) { return div_up(w.width, w.tile_w) * div_up(w.height, w.tile_h); }

// The group kernel's counts for the kernels pass w reads, and the pass's path with its hit fraction.
const GroupPathCounts& group_counts(const StageKernelCosts& c, const StageWork& w) {
  return w.gbuffer == GBufferRead::Fields60 ? c.group_paths_fields60 : c.group_paths;
}
GroupPath group_path_of(const StageWork& w) {
  GroupPath p = w.group_path;
  p.hit_fraction = w.pixels() ? double(w.rays) / double(w.pixels()) : 0.0;
  return p;
}

// The latency term of `blocks` blocks of shape b whose chain takes `chain` cycles, and what it was made of.
void set_latency(const GpuModelConfig& gpu, double blocks, const BlockShape& b, double chain, StageKernelTerms& t) {
  const double resident = resident_blocks(gpu, b);
  t.resident_warps = resident * div_up(b.threads, kWarp);
  t.chain_cycles = chain;
  t.latency_ms = stage_latency_ms(gpu, blocks, resident, chain);
}

// The generator's latency term: the group kernel's block chain (its trip-counted path only), or noopt's warp chain
// once per piece of its tile; the occupancy from the kernel's registers and shared memory (simt/stage_latency.h).
void generator_latency(const GpuModelConfig& gpu, const StageWork& w, double cycles, StageKernelTerms& t) {
  const StageKernelCosts& c = gpu.stages;
  const double m = double(w.tile_w) * w.tile_h, tiles = tiles_of(w);
  const StageLatencies l = stage_latencies(gpu);
  const bool fields = w.gbuffer == GBufferRead::Fields60;
  if (w.grouping) {
    const GroupPathCounts& paths = group_counts(c, w);
    if (w.group_path.k <= 0 || paths.empty()) return;
    const GroupPath p = group_path_of(w);
    const auto k = static_cast<uint32_t>(std::min(double(std::max(1, p.k)), m));
    const auto pixels = static_cast<uint32_t>(m);
    const BlockShape b{div_up(m, kWarp) * kWarp, c.group_regs,
                       double(tile_groups_bytes(pixels, (pixels + k - 1) / k, k)) + c.group_static_shared};
    set_latency(gpu, tiles, b, chain_cycles(l, group_block_chain(paths, p, m, tiles)), t);
    return;
  }
  const BlockShape b{div_up(std::min(m, kNooptPiece), kWarp) * kWarp, fields ? c.noopt_regs_fields60 : c.noopt_regs,
                     c.noopt_static_shared};
  set_latency(gpu, tiles, b, div_up(m, kNooptPiece) * chain_cycles(l, noopt_warp_chain(cycles)), t);
}

}  // namespace

// tile_hits: one 32-byte sector per pixel (its hit flag, prim), a count per tile written; blocks of 128 threads.
StageKernelTerms stage_tile_hits_terms(const GpuModelConfig& gpu, const StageWork& w) {
  const double tiles = tiles_of(w), tile_pixels = double(w.tile_w) * w.tile_h;
  const bool fields = w.gbuffer == GBufferRead::Fields60;
  return kernel_terms(gpu, double(w.pixels()) * kSectorBytes + 4.0 * tiles,
                      tiles * div_up(std::min(tile_pixels, kTileHitsThreads), kWarp),
                      fields ? gpu.stages.tile_hits_fields60 : gpu.stages.tile_hits,
                      l1_warp_wavefronts(gpu, w, tile_hits_l1(w.gbuffer)));
}

// The generator: a block per tile, a thread per pixel (noopt's block loops over tiles of more than 256 pixels, the
// same warps in all), reading the G-buffer (its records: 60 bytes before 63b5750) and writing the batch.
StageKernelTerms stage_generator_terms(const GpuModelConfig& gpu, const StageWork& w) {
  const double warps = tiles_of(w) * div_up(double(w.tile_w) * w.tile_h, kWarp);
  const StageKernelCosts& c = gpu.stages;
  const bool fields = w.gbuffer == GBufferRead::Fields60;
  double cycles = w.grouping ? (fields ? c.group_fields60 : c.group) : (fields ? c.noopt_fields60 : c.noopt);
  const GroupPathCounts& paths = group_counts(c, w);
  if (w.grouping && w.group_path.k > 0 && !paths.empty())
    cycles = group_path_instructions(paths, group_path_of(w), double(w.tile_w) * w.tile_h, tiles_of(w));
  const NooptPathCounts& lobes = fields ? c.noopt_paths_fields60 : c.noopt_paths;
  if (!w.grouping && w.noopt_path.known && !lobes.empty())
    cycles = noopt_path_instructions(lobes, w.noopt_path, double(w.tile_w) * w.tile_h, tiles_of(w));
  const double bytes = generation_bytes(w.pixels(), w.rays) -
                       double(w.pixels()) * (double(sizeof(ShadingPoint)) - gbuffer_record_bytes(w.gbuffer));
  StageKernelTerms t = kernel_terms(gpu, bytes, warps, cycles,
                                    l1_warp_wavefronts(gpu, w, w.grouping ? group_l1(w.gbuffer) : noopt_l1(w.gbuffer)));
  if (w.latency) generator_latency(gpu, w, cycles, t);
  return t;
}

double stage_generation_ms(const GpuModelConfig& gpu, const StageWork& w) {
  if (w.rays == 0 || w.pixels() == 0) return 0.0;
  double ms = stage_tile_hits_terms(gpu, w).ms(gpu);
  ms += scan_ms(gpu, tiles_of(w) + 1);
  return ms + stage_generator_terms(gpu, w).ms(gpu);
}

// A thread per ray in blocks of 256; the latency term (StageWork::latency): a block's chain is its warps' (each the
// ray's read and the kernel's count; MLHCC's walks, simt/stage_latency.h), the occupancy from its registers.
StageKernelTerms stage_key_terms(const GpuModelConfig& gpu, const StageWork& w) {
  if (w.key_bits == 0 || w.rays == 0) return {};
  const int kind = static_cast<int>(w.key);
  double cycles = kind >= 0 && kind < 7 ? gpu.stages.key[kind] : 0.0;
  if (w.key == KeyKind::Mlhcc) cycles = mlhcc_walk_instructions(cycles, gpu.stages.mlhcc_walk_body, w.mlhcc_walks);
  StageKernelTerms t = kernel_terms(gpu, key_bytes(w.rays, w.key_bits), div_up(double(w.rays), kWarp), cycles, 0);
  if (w.latency && kind > 0 && kind < 7) {
    const double walks = w.key == KeyKind::Mlhcc ? w.mlhcc_walks.origin + w.mlhcc_walks.end : 0.0;
    set_latency(gpu, div_up(double(w.rays), kKeyThreads), BlockShape{kKeyThreads, gpu.stages.key_regs[kind], 0},
                chain_cycles(stage_latencies(gpu), key_warp_chain(cycles, walks)), t);
  }
  return t;
}

double stage_key_ms(const GpuModelConfig& gpu, const StageWork& w) {
  if (w.key_bits == 0 || w.rays == 0) return 0.0;
  return stage_key_terms(gpu, w).ms(gpu);
}

double stage_sort_ms(const GpuModelConfig& gpu, size_t n, int key_bits) {
  if (key_bits == 0 || n < 2) return 0.0;
  const StageKernelCosts& c = gpu.stages;
  const bool wide = key_bits > 32;
  const double key = wide ? 8.0 : 4.0, value = 4.0;  // CUB sorts 32- or 64-bit words (cuda/device_keys.cu)
  const int passes = (key_bits + 7) / 8;
  // Histogram (reads the keys once) and exclusive sum (a few KB): launch-bound kernels.
  double ms = stage_kernel_ms(gpu, double(n) * key, 0, 0) + stage_launch_ms(gpu);
  const double tile = double(c.onesweep_threads) * (wide ? c.onesweep_items64 : c.onesweep_items32);
  const double warps = div_up(double(n), tile) * (c.onesweep_threads / kWarp);
  const double pass = std::max(stage_stream_ms(gpu, 2.0 * double(n) * (key + value)),
                               stage_issue_ms(gpu, warps, wide ? c.onesweep64 : c.onesweep32));
  ms += passes * (cycles_ms(gpu, kOnesweepPassFloorCycles) + pass);
  return ms;
}

double stage_permute_ms(const GpuModelConfig& gpu, double permute_bytes, size_t n) {
  if (n == 0) return 0.0;
  return stage_permute_terms(gpu, permute_bytes, n).ms(gpu);
}

StageKernelTerms stage_permute_terms(const GpuModelConfig& gpu, double permute_bytes, size_t n) {
  return kernel_terms(gpu, permute_bytes, div_up(double(n), kWarp), gpu.stages.gather, 0);
}

ModeledStages stage_model(const GpuModelConfig& gpu, const StageWork& w, const std::vector<uint32_t>& order) {
  ModeledStages m = stage_traffic(w.pixels(), w.key_bits, w.window, w.physical, w.rays, order);
  m.gen_ms = stage_generation_ms(gpu, w);
  if (w.key_bits == 0) return m;
  if (w.window > 0) {  // one on-chip binning kernel: its bytes and one launch, written as the sort
    m.sort_ms = w.rays < 2 ? 0.0 : stage_kernel_ms(gpu, m.sort_bytes, 0, 0);
    return m;
  }
  m.key_ms = stage_key_ms(gpu, w);
  m.sort_ms = stage_sort_ms(gpu, w.rays, w.key_bits);
  if (w.physical) m.permute_ms = stage_permute_ms(gpu, m.permute_bytes, w.rays);
  return m;
}

// The device pipeline's stage kernels (StageKernelCosts, simt/stage_model.h): partition cycles per warp counted by
// scripts/count-stage-instructions (nvcc 13's SASS of cuda/device_*.cu and CUB 3.0's onesweep kernel, every
// branch and loop body once). The generation kernels' counts (tile_hits, noopt, group) are those of the 64-byte
// G-buffer read with 16-byte loads (core/shading_point.h), results/model/wide-gbuffer-loads/instructions-*.txt; the
// others are unchanged from results/model/h200-stages/instructions-*.txt, which the h200 prediction used.
// CUB's onesweep tile, from its tuning (cub/device/dispatch/tuning/tuning_radix_sort.cuh, CUDA 13): sm_90
// (Policy900, sm90_small_key_tuning) 384 threads x 23 items for 32-bit keys with 32-bit values and 32-bit offsets,
// 30 for 64-bit keys; sm_86 (Policy800) 384 x 21 for both.
StageKernelCosts stage_costs_sm90() {
  StageKernelCosts c;
  c.tile_hits = 168;
  c.noopt = 1599;
  c.group = 7186;
  c.tile_hits_fields60 = 172;  // the a26f7f6 kernels: results/model/h200-stages/instructions-sm_90.txt
  c.noopt_fields60 = 1620;
  c.group_fields60 = 7241;
  c.group_paths = group_paths_sm90();  // results/model/stage-trip-counts/group-paths-*sm_90.txt
  c.group_paths_fields60 = group_paths_sm90_fields60();
  c.noopt_paths = noopt_paths_sm90();  // results/model/stage-trip-counts/noopt-paths-*sm_90.txt
  c.noopt_paths_fields60 = noopt_paths_sm90_fields60();
  c.mlhcc_walk_body[0] = 134;  // instructions-sm_90.txt, key mlhcc's loop bodies
  c.mlhcc_walk_body[1] = 135;
  const double keys[7] = {0, 270, 480, 428, 540, 680, 536};  // none, origin, reis, costa, aila, twopoint, mlhcc
  std::copy(keys, keys + 7, c.key);
  c.gather = 160;
  c.onesweep32 = 4120;
  c.onesweep64 = 2894;
  // The latency term: Accel-Sim's SM80_A100 configuration (the h100 preset's latency source; gpgpu-sim_distribution
  // configs/tested-cfgs/SM80_A100/gpgpusim.config: -ptx_opcode_latency_int and _fp 4 for add, max, mul and mad,
  // -gpgpu_smem_latency 28); compute capability 9.0's 228 KB of shared memory per SM (CUDA C++ Programming Guide);
  // registers and static shared memory: ptxas -v, nvcc 13, sm_90 (results/model/stage-latency/registers-sm_90.txt).
  c.alu_latency = 4;
  c.shared_latency = 28;
  c.shared_per_sm = 228 * 1024;
  c.group_regs = 64;  // both revisions (__launch_bounds__(1024) caps it)
  c.noopt_regs = 64;
  c.noopt_regs_fields60 = 62;
  const double regs[7] = {0, 21, 24, 23, 26, 28, 38};  // key kernels, both revisions
  std::copy(regs, regs + 7, c.key_regs);
  c.group_static_shared = 176;
  c.noopt_static_shared = 160;
  return c;
}

StageKernelCosts stage_costs_sm86() {
  StageKernelCosts c;
  c.tile_hits = 166;
  c.noopt = 1577;
  c.group = 7015;
  c.tile_hits_fields60 = 170;  // the a26f7f6 kernels: results/model/h200-stages/instructions-sm_86.txt
  c.noopt_fields60 = 1604;
  c.group_fields60 = 7068;
  c.group_paths = group_paths_sm86();  // results/model/stage-trip-counts/group-paths-*sm_86.txt
  c.group_paths_fields60 = group_paths_sm86_fields60();
  c.noopt_paths = noopt_paths_sm86();  // results/model/stage-trip-counts/noopt-paths-*sm_86.txt
  c.noopt_paths_fields60 = noopt_paths_sm86_fields60();
  c.mlhcc_walk_body[0] = 134;  // instructions-sm_86.txt
  c.mlhcc_walk_body[1] = 135;
  const double keys[7] = {0, 268, 480, 428, 538, 680, 502};
  std::copy(keys, keys + 7, c.key);
  c.gather = 146;
  c.onesweep32 = 3892;
  c.onesweep64 = 2142;
  c.onesweep_items32 = c.onesweep_items64 = 21;
  // The latency term: Accel-Sim's SM86_RTX3070 configuration (the rtx3060 preset's latency source;
  // -ptx_opcode_latency_int and _fp 4, -gpgpu_smem_latency 29); compute capability 8.6's 100 KB of shared memory
  // per SM (CUDA C++ Programming Guide); ptxas -v, nvcc 13, sm_86 (results/model/stage-latency/registers-sm_86.txt).
  c.alu_latency = 4;
  c.shared_latency = 29;
  c.shared_per_sm = 100 * 1024;
  c.group_regs = 64;
  c.noopt_regs = 64;
  c.noopt_regs_fields60 = 62;
  const double regs[7] = {0, 23, 25, 25, 26, 27, 38};
  std::copy(regs, regs + 7, c.key_regs);
  c.group_static_shared = 176;
  c.noopt_static_shared = 160;
  return c;
}

}  // namespace raycoh
