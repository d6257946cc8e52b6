// The stage model (simt/stage_model.h): its form on known inputs, each term where it should decide, and the h200
// preset.
#include "simt/stage_model.h"

#include <gtest/gtest.h>

#include <vector>

#include "core/error.h"
#include "encoders/encoder.h"
#include "generators/generator.h"
#include "simt/gpu_model.h"
#include "simt/pipeline_model.h"

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

}  // namespace
}  // namespace raycoh
