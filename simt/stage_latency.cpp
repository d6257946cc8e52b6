// The latency term's chains and occupancy; see simt/stage_latency.h and docs/simt-model.md section 3.
#include "simt/stage_latency.h"

#include <algorithm>
#include <cmath>

namespace raycoh {

StageLatencies stage_latencies(const GpuModelConfig& gpu) {
  return StageLatencies{gpu.stages.alu_latency, gpu.stages.shared_latency, gpu.gpu.l1_latency, gpu.gpu.l2_latency,
                        gpu.gpu.dram_latency};
}

LatencyChain& LatencyChain::operator+=(const LatencyChain& o) {
  instructions += o.instructions;
  shared += o.shared;
  l1 += o.l1;
  l2 += o.l2;
  dram += o.dram;
  return *this;
}

LatencyChain scaled(const LatencyChain& c, double f) {
  return LatencyChain{c.instructions * f, c.shared * f, c.l1 * f, c.l2 * f, c.dram * f};
}

double chain_cycles(const StageLatencies& l, const LatencyChain& c) {
  const auto beyond = [&l](double latency) { return std::max(0.0, latency - l.alu); };
  return c.instructions * l.alu + c.shared * beyond(l.shared) + c.l1 * beyond(l.l1) + c.l2 * beyond(l.l2) +
         c.dram * beyond(l.dram);
}

// CUDA C++ Programming Guide, "Compute Capabilities" (the limits) and the occupancy calculator's rules: registers
// are allocated per warp in units of reg_alloc_unit; the driver reserves 1 KB of shared memory per block (8.x, 9.0).
double resident_blocks(const GpuModelConfig& gpu, const BlockShape& b) {
  if (b.registers <= 0 || b.threads <= 0) return 0;
  const GpuSpec& g = gpu.gpu;
  const double warps = std::ceil(b.threads / 32);
  const double unit = std::max(1u, g.reg_alloc_unit);
  const double warp_regs = std::ceil(b.registers * 32 / unit) * unit;
  double n = std::min({double(g.max_blocks_per_sm), std::floor(g.max_warps_per_sm / warps),
                       std::floor(g.regs_per_sm / (warps * warp_regs))});
  if (gpu.stages.shared_per_sm > 0)
    n = std::min(n, std::floor(gpu.stages.shared_per_sm / (b.shared_bytes + kSharedReservedPerBlock)));
  return std::max(1.0, n);
}

double stage_latency_ms(const GpuModelConfig& gpu, double blocks, double resident, double cycles) {
  if (resident <= 0 || blocks <= 0) return 0;
  const double waves = std::ceil(blocks / (double(gpu.cache.sms) * resident));
  return waves * cycles / (gpu.gpu.clock_mhz * 1e3);
}

namespace {

LatencyChain chain(double instructions, double shared, double l1 = 0, double l2 = 0, double dram = 0) {
  return LatencyChain{instructions, shared, l1, l2, dram};
}

}  // namespace

// The phases of generators/grouping_block.h as cuda/device_grouping.cuh runs them, barriers between (a phase lasts
// its longest warp's chain). Loads on each chain, from the source (a loop's iterations taken one after another):
//   set-up, phase 1, the two block scans, the batch write (every warp): the pixel's G-buffer word (DRAM), the two
//     scans' warp totals (shared, one each), the tile's offset (L2);
//   member rank (every warp): per slot its pixel (at_slot) then that pixel's flags (shared, 2 per slot);
//   census (group threads): per slot at_slot then the pixel's flags and class (2 per slot);
//   positions: per member its pixel (members) then its class (2 per member);
//   own lobe (tiles with a lane off the all-diffuse path): the record (DRAM), its material (L1), the donor's normal
//     through group_of and donor (shared 2, L2);
//   shared direction (group threads): the group's type, count and donor (shared 1), the donor's normal (L2), per
//     member its pixel then its flags (2 per member); hybrid=glossy's branch in the tiles holding hybrid groups:
//     the same per member, and the chosen member's record (DRAM) and material (L1);
//   reuse (every warp): its group and that group's direction (shared 2), its record (DRAM) and material (L1).
LatencyChain group_block_chain(const GroupPathCounts& c, const GroupPath& p, double tile_pixels, double tiles) {
  const double m = std::max(1.0, tile_pixels), k = std::min(double(std::max(1, p.k)), m);
  const double warps = std::ceil(m / 32), members = k * std::clamp(p.hit_fraction, 0.0, 1.0);
  const double blocks = std::max(1.0, tiles);
  const double nondiffuse = std::min(1.0, p.nondiffuse_groups / blocks);
  const double hybrid = std::min(1.0, p.hybrid_groups / blocks);
  LatencyChain n = chain(region_instructions(c.common, warps), 2, 0, 1, 1);
  n += chain(region_instructions(c.member_rank, k), 2 * k);
  n += chain(region_instructions(c.census, k), 2 * k);
  n += chain(region_instructions(c.positions, members), 2 * members);
  n += scaled(chain(c.own_lobe.straight, 2, 1, 1, 1), nondiffuse);
  n += chain(region_instructions(c.shared_mean, members), 1 + 2 * members, 0, 1);
  if (p.hybrid_glossy) n += scaled(chain(region_instructions(c.shared_glossy, members), 2 * members, 1, 0, 1), hybrid);
  const double frame = p.rotate ? c.reuse_rotate.straight : c.reuse_local.straight;
  n += chain(c.reuse.straight + frame, 2, 1, 0, 1);
  if (p.hybrid_own) n += scaled(chain(c.reuse_own.straight, 0), hybrid);
  return n;
}

// noopt_kernel: the pixel's record (DRAM), its material (L1), the block scan's warp totals (shared), the tile's
// offset (L2).
LatencyChain noopt_warp_chain(double instructions) { return chain(instructions, 1, 1, 1, 1); }

// key_kernel: the ray (DRAM); MLHCC's walk (encoders/keys.h mlhcc_write_path): per iteration the node, then its
// cut's level for the child the point lies in, then that level's bits and offset, each needed by the next (the
// cut's top levels, shared by every ray: taken as L1 hits).
LatencyChain key_warp_chain(double instructions, double walks) {
  return chain(instructions, 0, 3 * std::max(0.0, walks), 0, 1);
}

}  // namespace raycoh
