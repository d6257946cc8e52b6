// The presets of the modelled GPUs, each value with its source. Nothing here was tuned to the paper's speedups:
// the paper's tables are the model's validation set (raycoh validate), not its training set.
#include <fmt/format.h>

#include <algorithm>

#include "core/error.h"
#include "core/params.h"
#include "simt/gpu_model.h"
#include "simt/stage_model.h"

namespace raycoh {
namespace {

constexpr uint64_t kKiB = 1024, kMiB = 1024 * 1024;

// The classic BVH2 kernel (`traversal=classic`, ClassicFetch in core/traverse.h) as nvcc 13.0 compiles it (the same
// source for both presets):
//   regs_per_thread: `nvcc -Xptxas -v` on cuda/trace_kernels.cu reports 55 registers for persistent_kernel on
//     sm_86 and sm_90 (54 for simple_kernel), with a 352-byte stack frame (traversal stack and state in local memory).
//   step costs: scripts/count-step-instructions (SASS of probe kernels; every branch of a step counted once except
//     the rare FP64 edge fallback and the division's slow path). A step occupies a partition for the largest of
//     its instruction count (one dispatch per cycle) and its per-pipe cycles (CUDA C++ Programming Guide,
//     arithmetic throughput per SM per clock: integer/compare/select 64, FP32 128, conversions/special 16).
//     sm_86: node step 115 instructions = 115 cycles, 14 global loads, 18 local accesses; triangle 124 = 124,
//     10 loads; leaf bookkeeping 39 = 42, 4 local accesses; traversal_begin 28 = 28 (sm_90 within 4%). The ray
//     fetch is two 16-byte loads per lane (cuda/trace_kernels.cu, load_ray).
//   loads per 16-byte word of the record (core/bvh.h): a node's 14 are its 12 box floats and 2 child indices, one
//     4-byte load each (Vec3 is 12 bytes: nvcc does not widen them; scripts/count-ptx-step-instructions counts 14
//     ld.global per PTX node step too), at bytes 0-52: 4, 4, 4, 2 per word; a triangle's 10 are v0, prim, v1, v2
//     at bytes 0-12, 16-24, 32-40: 4, 3, 3.
KernelSpec classic_kernel() {
  KernelSpec k;
  k.kind = TraceKernel::Persistent;  // the `cuda` tracer's default kernel and block size
  k.block_threads = 128;
  k.regs_per_thread = 55;
  k.node = {115, 14, 18, {4, 4, 4, 2, 0}};
  k.triangle = {124, 10, 0, {4, 3, 3, 0, 0}};
  k.leaf = {42, 0, 4};
  k.ray_begin = {28, 2, 0};
  return k;
}

// The tuned BVH2 kernel (`traversal=tuned`, WideFetch in core/traverse.h), counted with the same method by
// scripts/count-cwbvh-step-instructions (nvcc 13's SASS of the probe kernels simt/probe/step_probes.cu probe_wide_*,
// whose state is in registers as in closest_hit; sm_86, sm_90 in brackets): node step 88 instructions = 98
// partition cycles [87 = 96] (ALU-bound: 49 integer/compare/select/min/max at half rate), 4 global loads (3
// LDG.E.128 and one LDG.E.64: ptxas narrows the fourth word to the two child references it uses; modelled as four
// 16-byte loads of the node's four words) and 3 local accesses (the stack's push and two pops; the state no longer
// lives in local memory); triangle 152 = 152 [155], 3 LDG.E.128 (v0 + prim, v1, v2), 0 local (more integer
// selects than the classic kernel's 124: the watertight test's axis permutation indexes registers, not local
// memory); leaf bookkeeping 26 = 34 [25 = 38], 1 local. traversal_begin computes what the classic kernel's does: 28.
// The slab test's min and max are one FMNMX each (slab_min / slab_max): with the conditional form (a compare and a
// select each) the node step was 112 = 146. Registers: 55 on sm_86, 54 on sm_90 (`nvcc -Xptxas -v`,
// persistent_kernel<.., WideBvhView, NoAlphaTest>), stack frame 256 bytes (the stack alone; the classic kernel's
// 352 hold the whole state).
KernelSpec tuned_kernel(uint32_t regs) {
  KernelSpec k = classic_kernel();
  k.node = {98, 4, 3, {1, 1, 1, 1, 0}};
  k.node.load_bytes = 16;
  k.triangle = {152, 3, 0, {1, 1, 1, 0, 0}};
  k.triangle.load_bytes = 16;
  k.leaf = {34, 0, 1};
  k.regs_per_thread = regs;
  return k;
}

// The CWBVH kernel's step costs, counted as the tuned BVH2's (scripts/count-cwbvh-step-instructions, SASS of the
// probe kernels in simt/probe/cwbvh_step_probes.cu, nvcc 13 for sm_86 [sm_90]): node step 409 instructions = 542
// partition cycles [404 = 540] (ALU-bound: 271 integer/compare/select instructions at half rate — byte permutes
// and min/max for the 8 children's 6 planes, the per-slot selector moves, masks), 5 global loads (the 80-byte
// node as five LDG.E.128), 2 local accesses (the stack's push and pop: closest_hit_cwbvh keeps the stack apart
// from the state since 2026-11, so the state is in registers); triangle step 154 = 154 [155], 3 LDG.E.128 (the
// triangle as three 16-byte words, load_triangle_wide). The Leaf step (entering the triangle loop) has no
// instructions of its own in closest_hit_cwbvh: it is costed as one triangle's bookkeeping, 2 instructions = 4
// cycles (probe_cw_triangle minus probe_cw_test). Registers: 66 on sm_86, 56 on sm_90 (`nvcc -Xptxas -v`,
// persistent_kernel<.., CwbvhView, NoAlphaTest>), stack frame 512 bytes. Until 2026-11 (state and stack in local
// memory, triangles as ten 4-byte loads): node 395 instructions = 496 cycles, 5 loads, 17 local accesses; triangle
// 126, 10 loads; 64 registers, 624-byte frame (all sm_86). Before 2026-11-27 the node step decoded each plane to
// world space with a multiply and two adds and branched per slot: 716 instructions = 722 cycles, 46 local accesses.
KernelSpec cwbvh_kernel(uint32_t regs) {
  KernelSpec k = classic_kernel();
  k.node = {542, 5, 2, {1, 1, 1, 1, 1}};
  k.node.load_bytes = 16;  // the node's five 16-byte words
  k.triangle = {154, 3, 0, {1, 1, 1, 0, 0}};
  k.triangle.load_bytes = 16;
  k.leaf = {4, 0, 0};
  k.regs_per_thread = regs;
  return k;
}

// The hardware presets' kernels; `regs_tuned` and `regs_cwbvh` from ptxas for the preset's architecture.
void set_kernels(GpuModelConfig& m, uint32_t regs_tuned, uint32_t regs_cwbvh) {
  m.classic = classic_kernel();
  m.tuned = tuned_kernel(regs_tuned);
  m.cwbvh = cwbvh_kernel(regs_cwbvh);
  m.kernel = m.tuned;
}

// Both: 128-byte lines of 32-byte sectors (CUDA C++ Best Practices Guide, "Coalesced Access to Global Memory").
// L1 associativity is not published: 4 sets as Accel-Sim's tuned configs (Khairy et al., ISCA 2020,
// tested-cfgs SM86_RTX3070 and SM80_A100), L2 16-way as there. The whole unified L1 is cache: the traversal
// kernel uses no shared memory (CC 8.6 and 9.0 allow a 0 KB carveout).
CacheModelConfig cache_geometry(uint32_t sms, uint64_t l1_bytes, uint64_t l2_bytes) {
  CacheModelConfig c;
  c.sms = sms;
  c.line_bytes = 128;
  c.sector_bytes = 32;
  c.l1.bytes = l1_bytes;
  c.l1.ways = l1_ways_for(l1_bytes, c.line_bytes);
  c.l2.bytes = l2_bytes;
  c.l2.ways = 16;
  return c;
}

GpuModelConfig rtx3060() {
  GpuModelConfig m;
  m.preset = "rtx3060";
  // GA106: 3584 CUDA cores / 128 per SM = 28 SMs (NVIDIA GeForce RTX 3060 specifications); 128 KB L1/shared per
  // SM (NVIDIA Ampere GA102 whitepaper, GA10x SM); 3 MB L2 (512 KB per 32-bit memory controller, GA102
  // whitepaper; the 3060 has a 192-bit bus, six controllers).
  m.cache = cache_geometry(28, 128 * kKiB, 3 * kMiB);
  GpuSpec& g = m.gpu;
  g.clock_mhz = 1777;  // boost clock, NVIDIA GeForce RTX 3060 specifications
  // Compute capability 8.6 (CUDA C++ Programming Guide, "Technical Specifications per Compute Capability"):
  // 4 warp schedulers per SM issuing one warp instruction per cycle each (GA102 whitepaper, four SM partitions),
  // 48 resident warps, 16 resident blocks, 64K registers per SM; registers are allocated per warp in units of
  // 256 (CUDA Occupancy Calculator, "register allocation unit size").
  g.schedulers_per_sm = 4;
  g.max_warps_per_sm = 48;
  g.max_blocks_per_sm = 16;
  g.regs_per_sm = 65536;
  g.reg_alloc_unit = 256;
  // L1: one load/store instruction enters the LSU pipe per cycle per SM, and the L1TEX tag stage resolves 4 sets
  // x 4 sectors per cycle on GV100 and later: a request touching more distinct lines takes more wavefronts, one
  // per cycle (NVIDIA's Greg Smith, NVIDIA developer forums: "How does the LSU execute load/store instructions in
  // the Ampere architecture", 2023, and "Pascal L1 cache", 2017; Nsight Compute Kernel Profiling Guide,
  // "wavefronts").
  g.l1_tags_per_clk = 4;
  // L2: GA106's L2 bandwidth is not published. We take the A100's published L2 read bandwidth per SM (5120
  // bytes/clock for 108 SMs, NVIDIA A100 Tensor Core GPU Architecture whitepaper) times 28 SMs. The least
  // certain figure of this preset: docs/simt-model.md gives the modeled ratios with half and twice this value.
  g.l2_bytes_per_clk = 5120.0 / 108.0 * 28.0;
  g.dram_gb_s = 360;  // 15 Gbps GDDR6 on a 192-bit bus (NVIDIA GeForce RTX 3060 specifications)
  // Latencies: Accel-Sim's SM86_RTX3070 config, tuned against the hardware (gpgpu_l1_latency 39,
  // gpgpu_l2_rop_latency 187, + dram_latency 254), of the order Jia et al. measured (L1 ~30, L2 ~190 cycles).
  g.l1_latency = 39;
  g.l2_latency = 187;
  g.dram_latency = 187 + 254;
  set_kernels(m, 55, 66);  // sm_86
  m.stages = stage_costs_sm86();
  return m;
}

GpuModelConfig h100() {
  GpuModelConfig m;
  m.preset = "h100";
  // H100 SXM5: 132 SMs, 256 KB L1/shared per SM, 50 MB L2 (NVIDIA H100 Tensor Core GPU Architecture whitepaper).
  // The L2 is modelled as one 50 MB cache, not as two partitions.
  m.cache = cache_geometry(132, 256 * kKiB, 50 * kMiB);
  GpuSpec& g = m.gpu;
  g.clock_mhz = 1980;  // max boost clock of the H100 SXM5 (NVIDIA H100 datasheet)
  // Compute capability 9.0 (CUDA C++ Programming Guide): 4 schedulers, 64 resident warps, 32 resident blocks,
  // 64K registers per SM, allocation unit 256.
  g.schedulers_per_sm = 4;
  g.max_warps_per_sm = 64;
  g.max_blocks_per_sm = 32;
  g.regs_per_sm = 65536;
  g.reg_alloc_unit = 256;
  g.l1_tags_per_clk = 4;  // as rtx3060 (GV100 and later); unused with l1_words
  // L1 rule measured on an H100 (bench/l1_probe.cu; results/gpu/h100-6f75752/README.md and h100-9566ba3/README.md:
  // Nsight Compute's data- and tag-stage wavefronts of every probed lane pattern): 4-byte data banks and 4 hashed
  // tag banks (hopper_l1_cycles, simt/warp_trace.h).
  g.l1_words = true;
  // L2: about 5.5 TB/s measured on the H100 PCIe, 114 SMs at 1755 MHz (Chips and Cheese, "Nvidia's H100: Funny
  // L2, and Tons of Bandwidth", 2023): 5.5e12 / 1.755e9 / 114 = 27.5 bytes per cycle per SM, times 132 SMs.
  g.l2_bytes_per_clk = 5.5e12 / 1.755e9 / 114.0 * 132.0;
  g.dram_gb_s = 3350;  // HBM3, H100 SXM5 (NVIDIA H100 datasheet)
  // Latencies: Accel-Sim's SM80_A100 config (the closest tuned data-centre part): 34, 200, 200 + 190.
  g.l1_latency = 34;
  g.l2_latency = 200;
  g.dram_latency = 200 + 190;
  set_kernels(m, 54, 56);  // sm_90
  m.stages = stage_costs_sm90();
  return m;
}

// The H200 SXM: the H100 SXM5's GH100 chip (132 SMs, the same SM and L2) with 141 GB of HBM3e (NVIDIA H200
// Tensor Core GPU datasheet, 2024: "the first GPU with HBM3e", 4.8 TB/s, the Hopper architecture of the H100).
GpuModelConfig h200() {
  GpuModelConfig m = h100();
  m.preset = "h200";
  // 132 SMs, 256 KB L1/shared per SM, 50 MB L2: the H100 SXM5's figures (NVIDIA H100 Tensor Core GPU
  // Architecture whitepaper), as the H200 keeps the GH100 chip of the H100 SXM5 (NVIDIA H200 datasheet: Hopper).
  m.cache = cache_geometry(132, 256 * kKiB, 50 * kMiB);
  GpuSpec& g = m.gpu;
  // Max boost clock 1980 MHz, as the H100 SXM5's (NVIDIA H100 datasheet; TechPowerUp GPU database, H200 SXM).
  g.clock_mhz = 1980;
  g.dram_gb_s = 4800;  // HBM3e, 4.8 TB/s (NVIDIA H200 datasheet)
  // Compute capability 9.0, the L1 rule measured on an H100, the L2 bandwidth per SM and the latencies: h100's
  // (the same SM and L2). Registers: sm_90's ptxas counts, as h100.
  return m;
}

// The GPU GPGPU-Sim simulates with the configuration scripts/gpgpusim-run uses (Accel-Sim's RTX 3070, performance
// mode), so that the model and the simulator run the same kernel on the same rays and the same GPU
// (docs/simt-model.md section 6). Every value is read from
//   $RAYCOH_GPGPUSIM_DIR/gpgpu-sim/configs/tested-cfgs/SM86_RTX3070/gpgpusim.config
// cited below as "cfg:LINE", or from the simulator's source (src/gpgpu-sim/, GPGPU-Sim 4.2, commit 667834cf).
// Nothing here was chosen by comparing with the simulator's cycles: it is the simulator's validation set.
GpuModelConfig gpgpusim_rtx3070() {
  GpuModelConfig m;
  m.preset = "gpgpusim-rtx3070";
  // 46 SMs (cfg:24 -gpgpu_n_clusters 46, cfg:25 one core per cluster). L1: cfg:95 -gpgpu_cache:dl1 S:4:128:256
  // (sectored, 4 sets x 256 ways x 128-byte lines = 128 KiB; cfg:92 -gpgpu_unified_l1d_size 128 with the
  // adaptive carve-out of cfg:90 gives it all to L1 when a kernel uses no shared memory, as ours). L2:
  // cfg:114 -gpgpu_cache:dl2 S:64:128:16 per sub-partition (64 sets x 16 ways x 128 bytes = 128 KiB), cfg:26
  // -gpgpu_n_mem 16 x cfg:27 -gpgpu_n_sub_partition_per_mchannel 2 = 32 sub-partitions: 4 MiB, 16 ways.
  // Sectors: 32 bytes (SECTOR_SIZE, src/gpgpu-sim/gpu-cache.h).
  m.cache = cache_geometry(46, 128 * kKiB, 4 * kMiB);
  GpuSpec& g = m.gpu;
  g.clock_mhz = 1132;        // cfg:31 -gpgpu_clock_domains 1132:1132:1132:3500.5 (core, interconnect, L2)
  g.schedulers_per_sm = 4;   // cfg:79 -gpgpu_num_sched_per_core 4 (cfg:82 one instruction per warp per cycle)
  g.max_warps_per_sm = 48;   // cfg:38 -gpgpu_shader_core_pipeline 1536:32 (1536 threads, warps of 32)
  g.max_blocks_per_sm = 32;  // cfg:39 -gpgpu_shader_cta 32
  g.regs_per_sm = 65536;     // cfg:34 -gpgpu_shader_registers 65536
  // shader_core_config::max_cta (src/gpgpu-sim/shader.cc) rounds registers per thread up to a multiple of 4:
  // 4 x 32 lanes = 128 registers per warp.
  g.reg_alloc_unit = 128;
  // cfg:94 -gpgpu_l1_banks 4 (cfg:111 -gpgpu_coalesce_arch 86; byte interleaving 32 and the linear bank function
  // are the defaults, gpu-sim.cc): a load instruction's accesses are its distinct 32-byte sectors, and
  // ldst_unit::process_memory_access_queue_l1cache (shader.cc) takes up to 4 of them a cycle, the highest address
  // first, until a bank repeats (l1_bank_cycles, simt/warp_trace.h). Before 2026-11-27 the preset used the
  // hardware presets' rule here (4 distinct lines per cycle), which the source does not implement.
  g.l1_tags_per_clk = 4;
  g.l1_banks = 4;
  // L2: memory_sub_partition::cache_cycle (src/gpgpu-sim/l2cache.cc) takes one request (a 32-byte sector) per L2
  // cycle per sub-partition: 32 sub-partitions (cfg:26, cfg:27) x 32 bytes, at the core clock (cfg:31).
  g.l2_bytes_per_clk = 32 * 32;
  // DRAM: 16 channels (cfg:26; cfg:149 one per controller) x 2-byte bus (cfg:150 -gpgpu_dram_buswidth 2) x 4 data
  // transfers per command cycle (cfg:152 -dram_data_command_freq_ratio 4) x 3500.5 MHz (cfg:31) = 448 GB/s.
  g.dram_gb_s = 16 * 2 * 4 * 3500.5e6 * 1e-9;
  g.l1_latency = 39;           // cfg:96 -gpgpu_l1_latency 39
  g.l2_latency = 187;          // cfg:140 -gpgpu_l2_rop_latency 187 (the rtx3060 preset's reading of it)
  g.dram_latency = 187 + 254;  // cfg:140 + cfg:141 -dram_latency 254
  // cfg:11 -gpgpu_kernel_launch_latency 5000: kernel_info_t (src/abstract_hardware_model.cc) starts its
  // m_kernel_TB_latency at it (+ blocks x cfg:12 -gpgpu_TB_launch_latency 0), and gpgpu_sim (gpu-sim.cc) issues no
  // block before that count reaches 0, inside the kernel's cycles. The rtx3060 and h100 presets leave it at 0: no
  // published figure for the hardware.
  g.launch_cycles = 5000;
  // The kernel as the simulator runs it: PTX, one instruction issued per cycle, not SASS. The step costs are the
  // PTX counts of scripts/count-ptx-step-instructions (the probe kernels of simt/probe/step_probes.cu compiled by
  // the simulator build's nvcc 11.8 for compute_86, every branch of a step counted once, as for SASS): node step
  // 146 instructions, 14 ld.global, 23 ld/st.local; triangle 134, 10, 0 (its pair differs by -1 local: none);
  // leaf 35, 0, 8; traversal_begin 32 beside the ray's two loads. Until 2026-11-27 this preset used the SASS costs
  // of classic_kernel() (115, 124, 39, 28). Registers: the simulator takes them from ptxas (nvcc 11.8, sm_86) on the
  // same PTX, which reports 55 for persistent_kernel<false, BvhView, NoAlphaTest> (raycoh.N.sm_86.ptxas), as
  // nvcc 13 does.
  set_kernels(m, 55, 66);
  m.stages = stage_costs_sm86();  // SASS, not the PTX the simulator runs: the stage kernels' PTX was not counted
  // The simulator issues each warp's PTX in program order and waits for every operand (its scoreboard), with the
  // latencies of cfg:55-62 and cfg:96: a step alone on its scheduler, every load an L1 hit, takes node 1,242,
  // triangle 1,353, leaf 135 cycles (scripts/count-ptx-step-instructions, "in-order issue"). nvcc leaves PTX
  // unscheduled (each load's value used by the next instruction); ptxas schedules the SASS a GPU runs, so the
  // hardware presets have none.
  m.classic.node = {146, 14, 23, {4, 4, 4, 2, 0}, 1242};
  m.classic.triangle = {134, 10, 0, {4, 3, 3, 0, 0}, 1353};
  m.classic.leaf = {35, 0, 8, {}, 135};
  m.classic.ray_begin = {32, 2, 0};
  // The tuned kernel's PTX (the same script, probe_wide_*): node 95 instructions, 4 ld.global.nc (16 bytes), 3
  // local, in-order 331 cycles; triangle 138, 3, 0, 1070; leaf 24, 0, 1, 80. Registers: nvcc 13's ptxas for sm_86
  // (55); the simulator build's were not read. The CWBVH kernel keeps its SASS costs (its PTX was
  // never counted): a known gap of this preset.
  m.tuned = m.classic;
  m.tuned.node = {95, 4, 3, {1, 1, 1, 1, 0}, 331, 16};
  m.tuned.triangle = {138, 3, 0, {1, 1, 1, 0, 0}, 1070, 16};
  m.tuned.leaf = {24, 0, 1, {}, 80};
  m.tuned.regs_per_thread = 55;
  m.kernel = m.tuned;
  return m;
}

}  // namespace

void use_kernel(GpuModelConfig& c, TraceKernelChoice k) {
  const KernelSpec& from = k == TraceKernelChoice::Bvh2Tuned     ? c.tuned
                           : k == TraceKernelChoice::Bvh2Classic ? c.classic
                                                                 : c.cwbvh;
  const TraceKernel kind = c.kernel.kind;
  const uint32_t block = c.kernel.block_threads, warp = c.kernel.warp_size;
  c.kernel = from;
  c.kernel.kind = kind;
  c.kernel.block_threads = block;
  c.kernel.warp_size = warp;
}

const char* to_string(TraceKernel k) { return k == TraceKernel::Persistent ? "persistent" : "simple"; }

namespace {

// Every preset, once: its name (the `preset` parameter, the CSVs' `preset` column) and what makes it. Each makes a
// config whose `preset` field is that name.
struct Preset {
  const char* name;
  GpuModelConfig (*make)();
};
constexpr Preset kPresets[] = {
    {"rtx3060", rtx3060}, {"h100", h100}, {"gpgpusim-rtx3070", gpgpusim_rtx3070}, {"h200", h200}};

}  // namespace

std::vector<std::string> gpu_preset_names() {
  std::vector<std::string> names;
  for (const Preset& p : kPresets) names.push_back(p.name);
  return names;
}

GpuModelConfig gpu_preset(const std::string& name) {
  for (const Preset& p : kPresets)
    if (name == p.name) return p.make();
  throw Error(fmt::format("unknown GPU preset '{}'; valid presets: {}", name, join(gpu_preset_names())));
}

uint32_t resident_warps(const GpuModelConfig& c) {
  const GpuSpec& g = c.gpu;
  const uint32_t warps_per_block = c.kernel.block_threads / 32;
  const uint32_t regs_per_warp =
      (c.kernel.regs_per_thread * 32 + g.reg_alloc_unit - 1) / g.reg_alloc_unit * g.reg_alloc_unit;
  const uint32_t by_regs = g.regs_per_sm / regs_per_warp / warps_per_block;
  const uint32_t by_warps = g.max_warps_per_sm / warps_per_block;
  const uint32_t blocks = std::min({by_regs, by_warps, g.max_blocks_per_sm});
  if (blocks == 0)
    throw Error(fmt::format("simt: a block of {} threads with {} registers each does not fit on one SM",
                            c.kernel.block_threads, c.kernel.regs_per_thread));
  const uint32_t occupancy = blocks * warps_per_block;
  if (c.resident_override == 0) return occupancy;
  // An override is a what-if (resident=N); it keeps whole blocks.
  return std::max(warps_per_block, c.resident_override / warps_per_block * warps_per_block);
}

void validate(const GpuModelConfig& c) {
  validate(c.cache);
  const GpuSpec& g = c.gpu;
  if (!(g.clock_mhz > 0) || !(g.l1_tags_per_clk > 0) || !(g.l2_bytes_per_clk > 0) || !(g.dram_gb_s > 0) ||
      g.schedulers_per_sm == 0 || g.max_warps_per_sm == 0 || g.max_blocks_per_sm == 0 || g.reg_alloc_unit == 0)
    throw Error("simt: clock, schedulers, bandwidths and SM limits must be positive");
  if (!(g.l1_latency >= 0) || !(g.l2_latency >= g.l1_latency) || !(g.dram_latency >= g.l2_latency))
    throw Error(fmt::format("simt: latencies must grow from L1 to DRAM (got {}, {}, {} cycles)", g.l1_latency,
                            g.l2_latency, g.dram_latency));
  if (c.kernel.block_threads < 32 || c.kernel.block_threads > 1024 || c.kernel.block_threads % 32 != 0)
    throw Error(fmt::format("simt: block={} is not a multiple of 32 in [32, 1024]", c.kernel.block_threads));
  if (g.l1_banks != 0 && g.l1_words)
    throw Error("simt: l1_banks (GPGPU-Sim's rule) and l1_words (the H100's) exclude each other: set one to 0");
  if (g.l1_banks != 0 || g.l1_words) {
    if (g.l1_banks > 32 || (g.l1_banks & (g.l1_banks - 1)) != 0 || (g.l1_banks && c.cache.sector_bytes != 32))
      throw Error(fmt::format("simt: l1_banks={} needs a power of two in [1, 32] and 32-byte sectors (got {})",
                              g.l1_banks, c.cache.sector_bytes));
    for (const StepCost* s : {&c.kernel.node, &c.kernel.triangle, &c.tuned.node, &c.tuned.triangle, &c.classic.node,
                              &c.classic.triangle, &c.cwbvh.node, &c.cwbvh.triangle}) {
      uint32_t words = 0;
      for (uint8_t n : s->word_loads) words += n;
      if (words != s->global_loads)
        throw Error(
            fmt::format("simt: a step's word_loads add up to {}, not its {} global loads", words, s->global_loads));
    }
  }
  resident_warps(c);  // throws when not one block fits
}

}  // namespace raycoh
