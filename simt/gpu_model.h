// The modelled GPU of the `simt` tracer: its cache geometry, the hardware figures its timing model uses, and the
// shape of the traversal kernel it runs. Every preset value is a published figure or a property of our own
// compiled kernel, with its source beside it in simt/gpu_presets.cpp; none is fitted to a speedup. How the
// figures are used: docs/simt-model.md. Host only.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "simt/cache_model.h"
#include "simt/stage_paths.h"
#include "simt/warp_trace.h"

namespace raycoh {

// Hardware figures of the timing model (simt/timed_replay.h).
struct GpuSpec {
  double clock_mhz = 1777;          // SM clock the cycle counts are converted with
  uint32_t schedulers_per_sm = 4;   // warp instructions issued per SM per cycle
  uint32_t max_warps_per_sm = 48;   // resident warps allowed by the SM
  uint32_t max_blocks_per_sm = 16;  // resident thread blocks allowed by the SM
  uint32_t regs_per_sm = 65536;     // 32-bit registers per SM
  uint32_t reg_alloc_unit = 256;    // registers are allocated per warp in units of this many
  double l1_tags_per_clk = 4;       // L1 tag lookups (distinct 128-byte lines) per wavefront, one wavefront per cycle
  double l2_bytes_per_clk = 1024;   // L2 hit bandwidth of the whole GPU, bytes per SM cycle
  double dram_gb_s = 360;           // DRAM bandwidth, 1e9 bytes per second
  double l1_latency = 39;           // load-to-use cycles of an L1 hit
  double l2_latency = 187;          // load-to-use cycles of an L1 miss that hits in L2
  double dram_latency = 441;        // load-to-use cycles of an L2 miss
  double launch_cycles = 0;         // from the launch to the first block's start, part of the kernel time (0: none)
  // 0: a global load takes one L1 wavefront per l1_tags_per_clk distinct lines. > 0: GPGPU-Sim's rule, one access
  // per distinct 32-byte sector, l1_banks a cycle until a bank repeats (l1_bank_cycles, simt/warp_trace.h).
  uint32_t l1_banks = 0;
  // true: the H100's rule measured with bench/l1_probe.cu (hopper_l1_cycles, simt/warp_trace.h): a load's data
  // stage by 4-byte banks, its tag stage by 4 hashed tag banks, the larger of the two.
  bool l1_words = false;
  double dram_bytes_per_clk() const { return dram_gb_s * 1e3 / clock_mhz; }
};

enum class TraceKernel : uint8_t { Persistent, Simple };
const char* to_string(TraceKernel k);

// What one warp step of the kernel costs besides its data: the cycles its instructions occupy one SM partition
// (one dispatch per cycle, or its busiest pipe), its global load instructions (each one L1 request,
// whose tag stage needs a wavefront per `l1_tags_per_clk` distinct lines the active lanes touch) and its local
// memory instructions (the traversal stack and state; one wavefront each, the lanes' addresses interleaved).
// word_loads[w]: how many of the global loads read the record's 16-byte word w (used by the l1_banks and l1_words
// rules); load_bytes: the width of those loads (l1_words).
// inorder_cycles: a warp's time for the step when it issues in program order, waiting for each operand, alone on
// its scheduler with every load an L1 hit (0: its instructions issue back to back after its data).
struct StepCost {
  double issue_cycles = 0;
  uint32_t global_loads = 0;
  uint32_t local_accesses = 0;
  std::array<uint8_t, kMaxRecordWords> word_loads{};
  double inorder_cycles = 0;
  uint32_t load_bytes = 4;
};

// The kernel being modelled: the `cuda` tracer's launch and its per-step costs (scripts/count-step-instructions).
struct KernelSpec {
  TraceKernel kind = TraceKernel::Persistent;
  uint32_t block_threads = 128;  // threads per block, a multiple of 32
  uint32_t warp_size = 32;       // lanes per warp (the `simt` tracer's `warp`)
  uint32_t regs_per_thread = 55;
  StepCost node{115, 14, 18, {4, 4, 4, 2, 0}}, triangle{124, 10, 0, {4, 3, 3, 0, 0}}, leaf{42, 0, 4};
  StepCost ray_begin{28, 2, 0};             // fetch of 32 rays (two 16-byte loads per lane) and traversal_begin
  uint32_t ray_bytes = 32, hit_bytes = 16;  // one ray read and one hit written per lane
};

// The kernels of the `cuda` tracer the model can stand for (cuda/trace_kernels.h): the BVH2 kernel tuned (16-byte
// loads, state in registers; `traversal=tuned`, the default) or classic (a 4-byte load per field, the whole state
// in local memory; `traversal=classic`), and the CWBVH kernel (`bvh=cwbvh`).
enum class TraceKernelChoice : uint8_t { Bvh2Tuned, Bvh2Classic, Cwbvh };

// The device pipeline's stage kernels (cuda/device_generators.cu, device_grouping.cu, device_keys.cu,
// device_stages.cu, and CUB's onesweep pass) as the stage model prices them (simt/stage_model.h): the cycles one
// warp of each kernel occupies an SM partition, from its SASS counted by scripts/count-stage-instructions for the
// preset's architecture (every branch and every loop body once), and CUB's onesweep tile for the architecture
// (its tuning policy). 0: the preset has no count (that kernel is priced by its bytes alone).
struct StageKernelCosts {
  double tile_hits = 0;   // a tile's hit count (blocks of 128 threads, one per tile)
  double noopt = 0;       // the noopt generator (a block per tile, a thread per pixel)
  double group = 0;       // the ours / contiguous group kernel (a block per tile, a thread per pixel)
  double key[7] = {};     // the key kernel of each KeyKind (index = the enum's value; [0] = none), 32-bit keys
  double gather = 0;      // the gather of every batch column (a thread per ray)
  double onesweep32 = 0;  // one onesweep pass, 32-bit keys with 32-bit values: per warp of the tile
  double onesweep64 = 0;  // the same with 64-bit keys (key_bits > 32)
  uint32_t onesweep_threads = 384, onesweep_items32 = 23, onesweep_items64 = 30;  // CUB's tile
  // The three generation kernels before 63b5750 (60-byte G-buffer records read field by field, GBufferRead::Fields60),
  // to price the runs made with them.
  double tile_hits_fields60 = 0, noopt_fields60 = 0, group_fields60 = 0;
  // The group kernel by region, for its trip-counted count (simt/stage_paths.h); empty: the static count `group`.
  GroupPathCounts group_paths, group_paths_fields60;
  NooptPathCounts noopt_paths, noopt_paths_fields60;  // the noopt kernel by region (simt/stage_paths.h)
  double mlhcc_walk_body[2] = {0, 0};  // MLHCC's two cut-walk loop bodies (origin, end point), SASS instructions
  // The latency term (simt/stage_latency.h): the dependent ALU and shared-memory load latencies (SM cycles), the
  // shared memory per SM (bytes), and each kernel's registers per thread and static shared memory (ptxas -v of
  // nvcc 13; results/model/stage-latency/registers-*.txt). 0 registers: the kernel has no latency term.
  double alu_latency = 0, shared_latency = 0, shared_per_sm = 0;
  double group_regs = 0, noopt_regs = 0, noopt_regs_fields60 = 0, key_regs[7] = {};
  double group_static_shared = 0, noopt_static_shared = 0;
};

struct GpuModelConfig {
  std::string preset;  // one of gpu_preset_names()
  CacheModelConfig cache;
  GpuSpec gpu;
  KernelSpec kernel;  // the kernel modelled: `tuned` unless use_kernel() chose another
  // The preset's step costs of each kernel, counted from the code its GPU runs (sources in simt/gpu_presets.cpp).
  KernelSpec tuned, classic, cwbvh;
  uint32_t resident_override = 0;  // 0: occupancy from the kernel's registers and block size
  StageKernelCosts stages;         // the pipeline's stage kernels (simt/stage_model.h)
};

// Makes `kernel` the preset's costs of k (its launch shape, kind and block, kept).
void use_kernel(GpuModelConfig& c, TraceKernelChoice k);

std::vector<std::string> gpu_preset_names();  // the presets of simt/gpu_presets.cpp, in their table's order
// Throws raycoh::Error for an unknown name, naming the valid ones.
GpuModelConfig gpu_preset(const std::string& name);

// Resident warps per SM of the kernel: the register file, the block limit and the warp limit, in whole blocks
// (CUDA occupancy rules). Throws raycoh::Error when not even one block fits.
uint32_t resident_warps(const GpuModelConfig& c);

// Rays the `simt` tracer with these parameters ("preset=h100,...") keeps resident on the whole modelled GPU: SMs x
// resident warps per SM (resident_warps) x lanes per warp, one wave of its batch. Throws raycoh::Error on a bad
// parameter, as the tracer would. Defined in simt/simt_tracer.cpp.
uint64_t simt_resident_rays(const std::string& params);

// Throws raycoh::Error naming the offending value (cache geometry, non-positive rates, block size).
void validate(const GpuModelConfig& c);

}  // namespace raycoh
