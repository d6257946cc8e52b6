// What `raycoh table --generators noopt,ours,contiguous --encoders none,twopoint,mlhcc --tracers
// cpu,cuda,cuda:counters=on,simt` does with its batches, checked ray by ray (the table itself prints no hits): on
// cornell and sibenik, every generator's secondary batch reordered by every encoder (physical and indirect) is
// traced by `cuda` and by the counting kernel of `cuda:counters=on` with exactly the `cpu` tracer's hits, and the
// counting kernel's per-warp counters equal simt_trace_warp's warp by warp. 48x32 at the simulator size
// (tests/gpu_test_size.h), 160x120 on a GPU. Skips cleanly without a GPU; label `gpu`.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/flush_denormals.h"
#include "cuda/cuda_device.h"
#include "cuda/trace_kernels.h"
#include "encoders/encoder.h"
#include "encoders/reorder.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "simt/simt.h"
#include "tests/gpu_test_size.h"
#include "tests/test_util.h"
#include "tests/trace_test_util.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

using test::differing_hits;
using test::trace_with;

// Warps whose counting-kernel counters differ from simt_trace_warp's (lane i traces rays[order[i]]); the kernel's
// hits go to `hits`.
size_t differing_warps(const Bvh& bvh, const std::vector<Ray>& rays, const std::vector<uint32_t>* order,
                       std::vector<Hit>& hits) {
  const SimtConfig layout = simt_config(bvh.view(), 32, 64, 32);
  std::vector<Ray> lanes = rays;
  if (order)
    for (size_t i = 0; i < order->size(); ++i) lanes[i] = rays[(*order)[i]];
  cuda::DeviceTracer device(bvh.view());
  hits.assign(lanes.size(), Hit{});
  std::vector<WarpStepCounters> gpu_warps;
  device.trace_counting(rays.data(), order ? order->data() : nullptr, lanes.size(), hits.data(), layout, 128,
                        gpu_warps);
  const size_t warps = (lanes.size() + 31) / 32;
  if (gpu_warps.size() != warps) return warps;
  const FlushDenormalsScope ftz;  // the CPU tracers' floating-point mode, which the traversal kernels share
  std::vector<Hit> simt_hits(32);
  size_t differ = 0;
  for (size_t w = 0; w < warps; ++w) {
    CoherenceCounters c;
    simt_trace_warp(bvh.view(), lanes.data() + w * 32,
                    static_cast<uint32_t>(std::min<size_t>(32, lanes.size() - w * 32)), layout, simt_hits.data(), c);
    const WarpStepCounters& expected = c;
    differ += std::memcmp(&expected, &gpu_warps[w], sizeof(expected)) != 0;
  }
  return differ;
}

void expect_table_batches_match(const std::string& spec) {
  SCOPED_TRACE(spec);
  const int width = test::gpu_test_size(160, 48), height = test::gpu_test_size(120, 32);
  const Scene scene = load_scene(spec);
  const Bvh bvh = build_bvh(scene);
  auto cpu = make_tracer({"cpu", ""}, scene, bvh);
  auto cuda_timing = make_tracer({"cuda", ""}, scene, bvh);
  const GBuffer g =
      first_hits(scene, *cpu, width, height, make_pixel_order(width, height, RayOrder::Tile, 8, 8), 1, 0).gbuffer;
  for (const char* generator : {"noopt", "ours", "contiguous"}) {
    RayBatch batch;
    GenerationStats stats;
    make_generator({generator, ""})->generate(scene, g, 1, batch, stats);
    for (const char* encoder_name : {"none", "twopoint", "mlhcc"}) {
      for (PermuteMode mode : {PermuteMode::Physical, PermuteMode::Indirect}) {
        SCOPED_TRACE(std::string(generator) + "+" + encoder_name + " " + to_string(mode));
        auto encoder = make_encoder({encoder_name, ""}, EncoderContext{scene.bounds, &bvh});
        RayBatch sorted;
        std::vector<uint32_t> order;
        ReorderTimings times;
        const bool reordered = reorder(*encoder, batch, mode, sorted, order, times);
        const bool indirect = reordered && mode == PermuteMode::Indirect;
        const std::vector<Ray>& rays = reordered && !indirect ? sorted.rays : batch.rays;
        const std::vector<uint32_t>* lane_order = indirect ? &order : nullptr;
        const std::vector<Hit> want = trace_with(*cpu, rays, lane_order);
        EXPECT_EQ(differing_hits(trace_with(*cuda_timing, rays, lane_order), want), 0u);
        std::vector<Hit> counted;
        EXPECT_EQ(differing_warps(bvh, rays, lane_order, counted), 0u);
        EXPECT_EQ(differing_hits(counted, want), 0u);
      }
    }
  }
}

TEST(GpuTable, CudaHitsEqualCpuAndCountersEqualSimtOnEveryTableBatch) {
  if (cuda::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  expect_table_batches_match("cornell");
  for (const auto& path : test::shared_scene_files())
    if (path.filename() == "sibenik.glb") expect_table_batches_match(path.string());
}

}  // namespace
}  // namespace raycoh
