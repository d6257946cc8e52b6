// The stage model (simt/stage_model.h): its form on known inputs, each term where it should decide, and the h200
// preset.
#include "simt/stage_model.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "core/error.h"
#include "encoders/encoder.h"
#include "generators/generator.h"
#include "simt/gpu_model.h"
#include "simt/pipeline_model.h"
#include "simt/stage_l1.h"

namespace raycoh {
namespace {

StageWork noopt_pass(int width, int height) {
  StageWork w;
  w.width = width;
  w.height = height;
  w.rays = size_t(width) * size_t(height);
  return w;
}

TEST(StageModel, H200PresetValidatesAndHasItsDatasheetFigures) {
  const GpuModelConfig h200 = gpu_preset("h200");
  EXPECT_NO_THROW(validate(h200));
  EXPECT_EQ(h200.preset, "h200");
  EXPECT_EQ(h200.cache.sms, 132u);
  EXPECT_EQ(h200.gpu.dram_gb_s, 4800);
  EXPECT_EQ(h200.gpu.clock_mhz, 1980);
  EXPECT_EQ(h200.cache.l2.bytes, 50ull * 1024 * 1024);
  // The same SM and L2 as the h100 preset: only the memory differs.
  const GpuModelConfig h100 = gpu_preset("h100");
  EXPECT_EQ(h200.gpu.l2_bytes_per_clk, h100.gpu.l2_bytes_per_clk);
  EXPECT_EQ(resident_warps(h200), resident_warps(h100));
  EXPECT_GT(h200.stages.noopt, 0);
  EXPECT_EQ(h200.stages.onesweep_items32, 23u);
}

TEST(StageModel, EveryHardwarePresetHasStageCosts) {
  for (const std::string& name : gpu_preset_names()) {
    const GpuModelConfig c = gpu_preset(name);
    SCOPED_TRACE(name);
    EXPECT_GT(c.stages.tile_hits, 0);
    EXPECT_GT(c.stages.group, c.stages.noopt);
    for (int k = 1; k < 7; ++k) EXPECT_GT(c.stages.key[k], 0);
    EXPECT_GT(c.stages.onesweep32, 0);
  }
}

TEST(StageModel, TermsFollowTheirDefinitions) {
  const GpuModelConfig g = gpu_preset("h200");
  // 5000 cycles at 1980 MHz; 0.9 x 4.8 TB/s; 528 partitions at 1980 MHz.
  EXPECT_NEAR(stage_launch_ms(g), 5000 / 1980e3, 1e-12);
  EXPECT_NEAR(stage_stream_ms(g, 4.32e9), 1.0, 1e-12);
  EXPECT_NEAR(stage_issue_ms(g, 528, 1980e3), 1.0, 1e-12);
  // A kernel is its launch plus the larger term.
  EXPECT_NEAR(stage_kernel_ms(g, 4.32e9, 528, 1), stage_launch_ms(g) + 1.0, 1e-9);
  EXPECT_NEAR(stage_kernel_ms(g, 1, 528, 2 * 1980e3), stage_launch_ms(g) + 2.0, 1e-9);
}

TEST(StageModel, LaunchTermDominatesTinyBatches) {
  const GpuModelConfig g = gpu_preset("h200");
  StageWork w = noopt_pass(16, 8);  // two 8x8 tiles
  w.key = KeyKind::Origin;
  w.key_bits = 32;
  // Generation: tile_hits, the scan's two kernels and noopt: four launches and almost nothing else.
  const double gen = stage_generation_ms(g, w);
  EXPECT_GE(gen, 4 * stage_launch_ms(g));
  EXPECT_LT(gen, 4.05 * stage_launch_ms(g));
  const double key = stage_key_ms(g, w);
  EXPECT_LT(key - stage_launch_ms(g), 0.01 * key);
  // At 1080p the launches are a small share of generation.
  EXPECT_LT(4 * stage_launch_ms(g), 0.2 * stage_generation_ms(g, noopt_pass(1920, 1080)));
}

TEST(StageModel, SortGrowsWithKeyBitsByPasses) {
  const GpuModelConfig g = gpu_preset("h200");
  const size_t n = 2073600;
  const double s8 = stage_sort_ms(g, n, 8), s16 = stage_sort_ms(g, n, 16), s24 = stage_sort_ms(g, n, 24),
               s32 = stage_sort_ms(g, n, 32);
  // One onesweep pass per 8-bit digit, each the same cost: equal steps.
  EXPECT_GT(s16, s8);
  EXPECT_NEAR(s16 - s8, s24 - s16, 1e-12);
  EXPECT_NEAR(s32 - s24, s24 - s16, 1e-12);
  EXPECT_NEAR(stage_sort_ms(g, n, 30), s32, 1e-12);  // 30 bits still take four passes
  // A pass never costs less than its floor, however few the keys.
  EXPECT_GE(stage_sort_ms(g, 1000, 16) - stage_sort_ms(g, 1000, 8), kOnesweepPassFloorCycles / (1980e3));
  // 64-bit words: more bytes per pass than 32-bit ones.
  EXPECT_GT(stage_sort_ms(g, n, 40) - stage_sort_ms(g, n, 32), s32 - s24);
  EXPECT_EQ(stage_sort_ms(g, n, 0), 0.0);
}

TEST(StageModel, InstructionBoundStagePricedByItsInstructions) {
  GpuModelConfig g = gpu_preset("h200");
  StageWork w = noopt_pass(1920, 1080);
  w.key_bits = 32;
  w.key = KeyKind::TwoPoint;
  const double warps = double(w.rays) / 32;
  // TwoPoint's key kernel issues more than its bytes take: its time is its instructions.
  const double issue = stage_issue_ms(g, warps, g.stages.key[int(KeyKind::TwoPoint)]);
  ASSERT_GT(issue, stage_stream_ms(g, key_bytes(w.rays, 32)));
  EXPECT_NEAR(stage_key_ms(g, w), stage_launch_ms(g) + issue, 1e-12);
  // Doubling its instruction count doubles the term; bandwidth does not move it.
  g.stages.key[int(KeyKind::TwoPoint)] *= 2;
  EXPECT_NEAR(stage_key_ms(g, w), stage_launch_ms(g) + 2 * issue, 1e-12);
  g.gpu.dram_gb_s *= 2;
  EXPECT_NEAR(stage_key_ms(g, w), stage_launch_ms(g) + 2 * issue, 1e-12);
  // The group kernel costs more than noopt's on the same pass.
  StageWork ours = w;
  ours.grouping = true;
  EXPECT_GT(stage_generation_ms(g, ours), stage_generation_ms(g, w));
}

TEST(StageModel, BandwidthBoundStagePricedByItsBytes) {
  GpuModelConfig g = gpu_preset("h200");
  const size_t n = 2073600;
  std::vector<uint32_t> order(n);
  for (size_t i = 0; i < n; ++i) order[i] = static_cast<uint32_t>((i * 2654435761u) % n);
  const double bytes = permute_bytes(order.data(), n);
  ASSERT_GT(stage_stream_ms(g, bytes), stage_issue_ms(g, n / 32.0, g.stages.gather));
  const double t = stage_permute_ms(g, bytes, n);
  EXPECT_NEAR(t, stage_launch_ms(g) + stage_stream_ms(g, bytes), 1e-12);
  g.gpu.dram_gb_s /= 2;  // half the bandwidth: the bytes term doubles
  EXPECT_NEAR(stage_permute_ms(g, bytes, n) - stage_launch_ms(g), 2 * (t - stage_launch_ms(g)), 1e-12);
}

// The per-pixel generators (noopt, sadeghi, microjitter) run order=scanline as one-row tiles on the device
// (cuda/device_generators.cu plan): the model prices that grid, not the 8x8 tile of their tile order.
TEST(StageModel, ScanlinePerPixelGeneratorsArePricedWithTheirOneRowTiles) {
  const auto none = make_encoder({"none", ""}, EncoderContext{});
  for (const char* name : {"noopt", "sadeghi", "microjitter"}) {
    SCOPED_TRACE(name);
    const StageWork scan = stage_work(*make_generator({name, "order=scanline"}), *none, false, 64, 32, 100);
    EXPECT_EQ(scan.tile_w, 64);
    EXPECT_EQ(scan.tile_h, 1);
    const StageWork tile = stage_work(*make_generator({name, ""}), *none, false, 64, 32, 100);
    EXPECT_EQ(tile.tile_w * tile.tile_h, 64);
  }
}

// 32 lanes of `width` bytes, `stride` bytes apart from address 0.
double strided_wavefronts(const GpuModelConfig& g, uint32_t width, uint32_t stride) {
  uint64_t addr[32];
  for (uint32_t l = 0; l < 32; ++l) addr[l] = uint64_t{l} * stride;
  return l1_request_wavefronts(g, addr, 32, width);
}

// Counts by hand. Tag rule (rtx3060: 4 lines a wavefront, 128-byte data path): 4-byte lanes 60 bytes apart touch
// lines 0-14 (the last lane's bytes 1860-1863): 15 lines, 4 wavefronts; 16-byte lanes 64 bytes apart 16 lines and
// 512 bytes: 4. The H100's measured rule: 16-byte lanes 64 bytes apart are served 8 lanes a pass, and lanes i and
// i + 2 of a pass fall in the same four 4-byte banks (16 words apart): 4 words a bank, 4 passes, 16 wavefronts;
// 4-byte lanes 64 bytes apart: lanes i and i + 2 share a bank, 16 words in it, 16; 60 bytes apart: 15 words apart,
// every lane its own bank (15 is odd), and the 15 lines fall 3, 4, 4, 4 in the 4 hashed tag banks: 4.
TEST(StageModel, L1WavefrontsOfAStrideAndWidthFollowThePresetsRule) {
  const GpuModelConfig tags = gpu_preset("rtx3060"), h100 = gpu_preset("h100");
  EXPECT_EQ(strided_wavefronts(tags, 4, 60), 4);
  EXPECT_EQ(strided_wavefronts(tags, 16, 64), 4);
  EXPECT_EQ(strided_wavefronts(tags, 4, 4), 1);
  EXPECT_EQ(strided_wavefronts(h100, 16, 64), 16);
  EXPECT_EQ(strided_wavefronts(h100, 4, 64), 16);
  EXPECT_EQ(strided_wavefronts(h100, 4, 60), 4);
  EXPECT_EQ(strided_wavefronts(h100, 16, 16), 4);  // consecutive: 4 passes of 128 bytes
  EXPECT_EQ(strided_wavefronts(h100, 4, 0), 1);    // one address: a broadcast
}

// noopt since 63b5750 on 8x8 tiles under the tag rule, per warp (4 rows of 8 pixels): load_point's 4 loads touch
// 4 rows x 4 lines and 512 bytes: 4 each, 16; 16 one-address loads: 16; 6 Vec3-column stores (3 lines, 128
// bytes): 6; pixel and pdf: 2; the ray's 2 16-byte words at a 32-byte stride (8 lines, 512 bytes): 8; the class
// byte: 1. 49 in all.
TEST(StageModel, NooptL1InventoryCountsByHand) {
  const GpuModelConfig tags = gpu_preset("rtx3060");
  StageWork w = noopt_pass(1920, 1080);
  EXPECT_DOUBLE_EQ(l1_warp_wavefronts(tags, w, noopt_l1(GBufferRead::Wide64)), 49);
  EXPECT_DOUBLE_EQ(stage_generator_terms(tags, w).l1_wavefronts, 49);
  // The 60-byte records read field by field: 16 loads of at least 16 lines (4 wavefronts) each, at most 20 (5).
  w.gbuffer = GBufferRead::Fields60;
  const double fields = l1_warp_wavefronts(tags, w, noopt_l1(GBufferRead::Fields60));
  EXPECT_GE(fields, 49 - 16 + 16 * 4);
  EXPECT_LE(fields, 49 - 16 + 16 * 5);
}

TEST(StageModel, KernelIsItsLaunchPlusTheLargestOfThreeTerms) {
  const GpuModelConfig g = gpu_preset("h200");
  // 132 warps of 1980e3 wavefronts: 1980e3 cycles on each of the 132 SMs' L1 at 1980 MHz, 1 ms.
  EXPECT_NEAR(stage_l1_ms(g, 132, 1980e3), 1.0, 1e-12);
  EXPECT_NEAR(stage_kernel_ms(g, 0, 132, 0, 1980e3), stage_launch_ms(g) + 1.0, 1e-9);
  EXPECT_NEAR(stage_kernel_ms(g, 2 * 4.32e9, 132, 0, 1980e3), stage_launch_ms(g) + 2.0, 1e-9);      // bytes decide
  EXPECT_NEAR(stage_kernel_ms(g, 0, 132, 4 * 3 * 1980e3, 1980e3), stage_launch_ms(g) + 3.0, 1e-9);  // issue
}

// With the presets' constants the generation kernels are issue-bound (or DRAM-bound): the L1 term, priced at the
// L1-hit rule, stays below. With few instructions and a fast memory it decides.
TEST(StageModel, TheL1TermDecidesOnlyWhereItIsTheLargest) {
  for (const char* name : {"h100", "h200", "rtx3060"})
    for (const GBufferRead read : {GBufferRead::Fields60, GBufferRead::Wide64})
      for (const bool grouping : {false, true}) {
        SCOPED_TRACE(name);
        StageWork w = noopt_pass(1920, 1080);
        w.gbuffer = read;
        w.grouping = grouping;
        const StageKernelTerms t = stage_generator_terms(gpu_preset(name), w);
        EXPECT_GT(t.l1_ms, 0);
        EXPECT_LT(t.l1_ms, std::max(t.issue_ms, t.dram_ms));
      }
  GpuModelConfig g = gpu_preset("h200");
  g.stages.noopt = 1;
  g.gpu.dram_gb_s = 1e6;
  const StageKernelTerms t = stage_generator_terms(g, noopt_pass(1920, 1080));
  EXPECT_GT(t.l1_ms, std::max(t.issue_ms, t.dram_ms));
  EXPECT_NEAR(t.ms(g), stage_launch_ms(g) + t.l1_ms, 1e-12);
}

// The kernels before 63b5750: their instruction counts and 60-byte records.
TEST(StageModel, FieldByFieldKernelsArePricedWithTheirCountsAndRecords) {
  const GpuModelConfig g = gpu_preset("h200");
  StageWork w = noopt_pass(1920, 1080);
  const StageKernelTerms wide = stage_generator_terms(g, w);
  w.gbuffer = GBufferRead::Fields60;
  const StageKernelTerms fields = stage_generator_terms(g, w);
  EXPECT_NEAR(fields.issue_ms, stage_issue_ms(g, fields.warps, g.stages.noopt_fields60), 1e-15);
  EXPECT_NEAR(wide.dram_ms - fields.dram_ms, stage_stream_ms(g, 4.0 * 1920 * 1080), 1e-12);
}

}  // namespace
}  // namespace raycoh
