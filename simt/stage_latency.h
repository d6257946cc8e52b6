// The latency (critical-path) term of the stage model (simt/stage_model.h, docs/simt-model.md section 3): the time
// a kernel's longest dependent chain takes per block, times the blocks that must run one after another on an SM at
// the kernel's occupancy. A chain is a count of instructions issued in program order, each waiting for the one
// before (the dependent ALU latency each), and of the loads on it, each waiting for its data (the latency of the
// level it hits). The per-operation latencies are published simulator configurations (StageKernelCosts and
// GpuSpec cite them); the chains are counted from the kernels' source and the trip counts of simt/stage_paths.h.
// MODELED, never measured; a lower layer of simt/stage_model.h. Host only.
#pragma once

#include "simt/gpu_model.h"
#include "simt/stage_paths.h"

namespace raycoh {

// SM cycles from issue to use: a dependent ALU instruction, a shared-memory load, a global load hitting L1, L2 or
// DRAM.
struct StageLatencies {
  double alu = 0, shared = 0, l1 = 0, l2 = 0, dram = 0;
};
// The preset's: alu and shared from gpu.stages, l1 / l2 / dram from gpu.gpu.
StageLatencies stage_latencies(const GpuModelConfig& gpu);

// One dependent chain: `instructions` issued in order, each after the one before, and among them the loads that
// wait for their data, by the level they hit.
struct LatencyChain {
  double instructions = 0;
  double shared = 0, l1 = 0, l2 = 0, dram = 0;
  LatencyChain& operator+=(const LatencyChain& o);
};
LatencyChain scaled(const LatencyChain& c, double f);  // every count times f (a phase run by a share of blocks)
// instructions x alu + each load's latency beyond the alu's (a load is one of the instructions).
double chain_cycles(const StageLatencies& l, const LatencyChain& c);

// What a block holds of an SM: its threads, registers per thread (ptxas) and shared memory (static + dynamic).
struct BlockShape {
  double threads = 0, registers = 0, shared_bytes = 0;
};
// Shared memory the driver reserves per block on compute capability 8.0 and later (CUDA C++ Programming Guide,
// "Shared Memory" of compute capabilities 8.x and 9.0: 1 KB per thread block).
constexpr double kSharedReservedPerBlock = 1024;
// Resident blocks per SM (CUDA occupancy rules): the block limit, the warp limit, the register file (registers per
// warp rounded up to the allocation unit) and shared memory (plus the 1 KB the driver reserves per block), at least
// 1; 0 when the registers are unknown (0).
double resident_blocks(const GpuModelConfig& gpu, const BlockShape& b);

// `blocks` blocks whose chain takes `cycles`, `resident` at a time per SM: ceil(blocks / (SMs x resident)) waves
// of `cycles` each (milliseconds). 0 when resident is 0.
double stage_latency_ms(const GpuModelConfig& gpu, double blocks, double resident, double cycles);

// The chain of one block of the group kernel on tiles of `tile_pixels` pixels, `tiles` in all (the phases between
// its barriers, each its longest warp's; simt/stage_latency.cpp lists each phase's loads).
LatencyChain group_block_chain(const GroupPathCounts& c, const GroupPath& p, double tile_pixels, double tiles);
// The chain of one warp of the noopt kernel that runs `instructions` (its path's count).
LatencyChain noopt_warp_chain(double instructions);
// The chain of one warp of a key kernel that runs `instructions` (MLHCC: its trip-counted count) and, MLHCC,
// `walks` cut-walk iterations in all (each loads a node, its cut's level and that level's offset, in turn).
LatencyChain key_warp_chain(double instructions, double walks);

}  // namespace raycoh
