// The stage model's latency term (simt/stage_latency.h): chains, occupancy and waves, hand-counted.
#include "simt/stage_latency.h"

#include <gtest/gtest.h>

#include <cmath>

#include "simt/gpu_model.h"
#include "simt/stage_model.h"
#include "tests/stage_hand_counts.h"

namespace raycoh {
namespace {

const StageLatencies kLat{4, 28, 34, 200, 390};

TEST(StageLatency, ChainIsInstructionsAtTheAluLatencyPlusEachLoadBeyondIt) {
  // 100 x 4 + 2 x (28 - 4) + (34 - 4) + (200 - 4) + (390 - 4).
  EXPECT_DOUBLE_EQ(chain_cycles(kLat, LatencyChain{100, 2, 1, 1, 1}), 400 + 48 + 30 + 196 + 386);
  EXPECT_DOUBLE_EQ(chain_cycles(kLat, LatencyChain{}), 0);
  LatencyChain a{10, 1, 0, 0, 0};
  a += scaled(LatencyChain{20, 0, 2, 0, 1}, 0.5);
  EXPECT_DOUBLE_EQ(a.instructions, 20);
  EXPECT_DOUBLE_EQ(a.l1, 1);
  EXPECT_DOUBLE_EQ(a.dram, 0.5);
  // The preset's latencies: Accel-Sim SM80_A100's (h200 as h100).
  const StageLatencies h = stage_latencies(gpu_preset("h200"));
  EXPECT_DOUBLE_EQ(h.alu, 4);
  EXPECT_DOUBLE_EQ(h.shared, 28);
  EXPECT_DOUBLE_EQ(h.l1, 34);
  EXPECT_DOUBLE_EQ(h.l2, 200);
  EXPECT_DOUBLE_EQ(h.dram, 390);
}

TEST(StageLatency, ResidentBlocksFollowTheOccupancyRules) {
  const GpuModelConfig h = gpu_preset("h200");  // 64 warps, 32 blocks, 65536 registers (unit 256), 228 KB
  // 8x8 group tile: 2 warps of 64 registers = 4096 registers a block: 16 blocks.
  EXPECT_DOUBLE_EQ(resident_blocks(h, BlockShape{64, 64, 2576}), 16);
  // 62 registers round up to 2048 a warp: still 16.
  EXPECT_DOUBLE_EQ(resident_blocks(h, BlockShape{64, 62, 160}), 16);
  // 1024 threads of 64 registers fill the register file: 1.
  EXPECT_DOUBLE_EQ(resident_blocks(h, BlockShape{1024, 64, 0}), 1);
  // 256 threads of 38 registers: 38 x 32 = 1216 -> 1280 a warp, 10240 a block: 6 (65536 / 10240 = 6.4).
  EXPECT_DOUBLE_EQ(resident_blocks(h, BlockShape{256, 38, 0}), 6);
  // 32 threads of 16 registers: the block limit, 32.
  EXPECT_DOUBLE_EQ(resident_blocks(h, BlockShape{32, 16, 0}), 32);
  // Shared memory: 100 KB + 1 KB reserved a block into 228 KB: 2.
  EXPECT_DOUBLE_EQ(resident_blocks(h, BlockShape{64, 32, 100 * 1024}), 2);
  // Unknown registers: no term.
  EXPECT_DOUBLE_EQ(resident_blocks(h, BlockShape{64, 0, 0}), 0);
}

TEST(StageLatency, WavesAreWholeAndRunOneAfterAnother) {
  const GpuModelConfig h = gpu_preset("h200");  // 132 SMs, 1980 MHz
  // 32400 blocks, 16 a SM: ceil(32400 / 2112) = 16 waves of 1980 cycles = 16 us.
  EXPECT_NEAR(stage_latency_ms(h, 32400, 16, 1980), 0.016, 1e-12);
  // One block fewer than two full waves still takes two; one more takes three.
  EXPECT_NEAR(stage_latency_ms(h, 2 * 2112 - 1, 16, 1980), 0.002, 1e-12);
  EXPECT_NEAR(stage_latency_ms(h, 2 * 2112 + 1, 16, 1980), 0.003, 1e-12);
  EXPECT_DOUBLE_EQ(stage_latency_ms(h, 100, 0, 1980), 0);
}

using test::hand_counts;

// 8x8 tile (2 warps), every pixel hit, all groups diffuse, duff.
TEST(StageLatency, GroupBlockChainCountedByHand) {
  GroupPath p;
  p.k = 8;
  const LatencyChain c = group_block_chain(hand_counts(), p, 64, 100);
  // common 100 + 2 x 2, member rank 10 + 8 x 3, census 20 + 8 x 5, positions 30 + 8 x 7, mean 40 + 8 x 11,
  // reuse 50 + 60.
  EXPECT_DOUBLE_EQ(c.instructions, 104 + 34 + 60 + 86 + 128 + 110);
  // Shared: the scans 2, 2 per slot (rank, census: 16 each), 2 per member (positions 16), the mean 1 + 16, reuse 2.
  EXPECT_DOUBLE_EQ(c.shared, 2 + 16 + 16 + 16 + 17 + 2);
  EXPECT_DOUBLE_EQ(c.l1, 1);    // reuse's material
  EXPECT_DOUBLE_EQ(c.l2, 2);    // the tile's offset, the donor's normal
  EXPECT_DOUBLE_EQ(c.dram, 2);  // phase 1's word, reuse's record
  // k = 64 (one group): the per-slot and per-member loops run 64 times; the chain grows by 56 x (3 + 5 + 7 + 11)
  // instructions and 56 x 8 shared loads.
  p.k = 64;
  const LatencyChain d = group_block_chain(hand_counts(), p, 64, 100);
  EXPECT_DOUBLE_EQ(d.instructions - c.instructions, 56.0 * 26);
  EXPECT_DOUBLE_EQ(d.shared - c.shared, 56.0 * 8);
  // 25 of 100 tiles with a non-diffuse group: a quarter of the own lobe's chain (1000, shared 2, L1, L2, DRAM).
  p.k = 8;
  p.nondiffuse_groups = 25;
  const LatencyChain e = group_block_chain(hand_counts(), p, 64, 100);
  EXPECT_DOUBLE_EQ(e.instructions - c.instructions, 250);
  EXPECT_DOUBLE_EQ(e.dram - c.dram, 0.25);
}

TEST(StageLatency, KeyAndNooptChains) {
  // MLHCC: 30 walk iterations, three dependent L1 loads each, and the ray's read.
  const LatencyChain k = key_warp_chain(536, 30);
  EXPECT_DOUBLE_EQ(k.l1, 90);
  EXPECT_DOUBLE_EQ(k.dram, 1);
  EXPECT_DOUBLE_EQ(chain_cycles(kLat, k), 536 * 4 + 90 * 30 + 386);
  const LatencyChain n = noopt_warp_chain(694);
  EXPECT_DOUBLE_EQ(chain_cycles(kLat, n), 694 * 4 + 24 + 30 + 196 + 386);
}

StageWork sweep_pass(int tile_w, int tile_h, int k, bool latency) {
  StageWork w;
  w.width = 1920;
  w.height = 1080;
  w.rays = 1920 * 1080;
  w.grouping = true;
  w.tile_w = tile_w;
  w.tile_h = tile_h;
  w.group_path.k = k;
  w.latency = latency;
  return w;
}

TEST(StageLatency, OnlyWhenAskedAndThenTheLargerTerm) {
  const GpuModelConfig h = gpu_preset("h200");
  // Without it the kernel is as before (no latency term).
  const StageKernelTerms off = stage_generator_terms(h, sweep_pass(32, 8, 64, false));
  EXPECT_DOUBLE_EQ(off.latency_ms, 0);
  const StageKernelTerms on = stage_generator_terms(h, sweep_pass(32, 8, 64, true));
  EXPECT_GT(on.latency_ms, 0);
  EXPECT_DOUBLE_EQ(on.issue_ms, off.issue_ms);
  EXPECT_DOUBLE_EQ(on.ms(h) - off.ms(h),
                   std::max(0.0, on.latency_ms - std::max({off.dram_ms, off.issue_ms, off.l1_ms})));
  // 32x8 tiles, one warp of eight holds the group threads: the chain runs 4 blocks a SM (8 warps of 64 registers);
  // on 8x8 tiles 16. The same block chain at a quarter of the resident blocks: about 4x the waves of a quarter the
  // blocks, so the two terms are within the tiles' wave rounding of each other.
  const double small = stage_generator_terms(h, sweep_pass(8, 8, 64, true)).latency_ms;
  EXPECT_NEAR(on.latency_ms / small, 1.0, 0.1);
  // The latency term grows with k (the serial phases' loops).
  EXPECT_GT(on.latency_ms, stage_generator_terms(h, sweep_pass(32, 8, 8, true)).latency_ms * 2);
}

TEST(StageLatency, TermsSayWhatTheyWereMadeOf) {
  const GpuModelConfig h = gpu_preset("h200");
  // 32x8 tiles: 8 warps a block, 4 blocks a SM (above); the term is the block chain over whole waves of them.
  const StageKernelTerms on = stage_generator_terms(h, sweep_pass(32, 8, 64, true));
  EXPECT_DOUBLE_EQ(on.resident_warps, 32);
  EXPECT_GT(on.chain_cycles, 0);
  EXPECT_DOUBLE_EQ(on.latency_ms, stage_latency_ms(h, 60 * 135, 4, on.chain_cycles));
  EXPECT_DOUBLE_EQ(on.issue_ms, stage_issue_ms(h, on.warps, on.cycles));
  EXPECT_DOUBLE_EQ(on.dram_ms, stage_stream_ms(h, on.bytes));
  // Without the latency term only the count is said.
  const StageKernelTerms off = stage_generator_terms(h, sweep_pass(32, 8, 64, false));
  EXPECT_DOUBLE_EQ(off.cycles, on.cycles);
  EXPECT_DOUBLE_EQ(off.resident_warps, 0);
  EXPECT_DOUBLE_EQ(off.chain_cycles, 0);
  // The key kernel: blocks of 256 threads, its chain that of one warp.
  StageWork k;
  k.width = 1920;
  k.height = 1080;
  k.rays = 1920 * 1080;
  k.key = KeyKind::Origin;
  k.key_bits = 32;
  k.latency = true;
  const StageKernelTerms key = stage_key_terms(h, k);
  EXPECT_GT(key.resident_warps, 0);
  EXPECT_DOUBLE_EQ(std::fmod(key.resident_warps, 8), 0);
  EXPECT_DOUBLE_EQ(key.chain_cycles, chain_cycles(stage_latencies(h), key_warp_chain(key.cycles, 0)));
  // The gather: its bytes as given, a thread per ray, no latency term; the stage is its launch.
  const StageKernelTerms gather = stage_permute_terms(h, 5e7, k.rays);
  EXPECT_DOUBLE_EQ(gather.bytes, 5e7);
  EXPECT_DOUBLE_EQ(gather.warps, 1920 * 1080 / 32);
  EXPECT_DOUBLE_EQ(gather.chain_cycles, 0);
  EXPECT_DOUBLE_EQ(gather.ms(h), stage_permute_ms(h, 5e7, k.rays));
}

}  // namespace
}  // namespace raycoh
