// The `cuda` tracer (cuda/cuda_tracer.cpp, cuda/trace_kernels.cu) against the CPU: hits of every kernel and block
// size, direct and indirect, equal the `cpu` tracer's bit for bit; the counting kernel's per-warp counters equal
// simt/simt.h's simt_trace_warp warp by warp, and the tracer's totals equal the `simt` tracer's, on cornell,
// voxels and sibenik (primary and NoOpt secondary batches, a shuffled indirect order, lines of 64 and 128 bytes,
// batches that end in a partial warp and hold rejected rays). `cuda:bvh=cwbvh` equals `cpu:bvh=cwbvh` bit for bit
// and the BVH2 in t. The registry tests run without a GPU too; the others skip cleanly (GTEST_SKIP) when
// cuda::device_count() == 0. Label `gpu`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "core/flush_denormals.h"
#include "core/rng.h"
#include "cuda/cuda_device.h"
#include "cuda/trace_kernels.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "generators/primary.h"
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

#define SKIP_WITHOUT_GPU() \
  if (cuda::device_count() == 0) GTEST_SKIP() << "no CUDA device"

// One frame of a scene: the primary batch in tile order and the NoOpt secondary batch made from its hits.
struct SceneFrame {
  Scene scene;
  Bvh bvh;
  PixelRays primary;
  RayBatch secondary;
};

// 256x192 on a GPU, 64x48 at the simulator size (tests/gpu_test_size.h).
std::unique_ptr<SceneFrame> make_frame(const std::string& spec, int width = 0, int height = 0) {
  if (width == 0) width = test::gpu_test_size(256, 64);
  if (height == 0) height = test::gpu_test_size(192, 48);
  auto f = std::make_unique<SceneFrame>();
  f->scene = load_scene(spec);
  f->bvh = build_bvh(f->scene);
  auto cpu = make_tracer({"cpu", ""}, f->scene, f->bvh);
  f->primary = make_primary_rays(f->scene.camera, width, height, make_pixel_order(width, height, RayOrder::Tile, 8, 8),
                                 1, 0, true);
  std::vector<Hit> hits(f->primary.rays.size());
  cpu->trace(f->primary.rays.data(), hits.size(), hits.data());
  const GBuffer g = make_gbuffer(f->scene, f->primary, hits);
  GenerationStats stats;
  make_generator({"noopt", ""})->generate(f->scene, g, 1, f->secondary, stats);
  return f;
}

// cornell, voxels and (when the shared scenes are there) sibenik.
std::vector<std::string> scene_specs() {
  std::vector<std::string> specs = {"cornell", "voxels:size=48"};
  for (const auto& path : test::shared_scene_files())
    if (path.filename() == "sibenik.glb") specs.push_back(path.string());
  return specs;
}

// The secondary rays with stiff cases mixed in (rejected rays: NaN origin, zero direction, empty interval;
// axis-parallel directions) and a length that ends in a partial warp.
std::vector<Ray> stiff_batch(const RayBatch& batch) {
  std::vector<Ray> rays(batch.rays.begin(), batch.rays.end());
  if (rays.size() > 100) rays.resize(rays.size() - 13);
  for (size_t i = 0; i < rays.size(); i += 97) rays[i].org.x = std::nanf("");
  for (size_t i = 5; i < rays.size(); i += 101) rays[i].dir = Vec3{0.f, 0.f, 0.f};
  for (size_t i = 9; i < rays.size(); i += 103) rays[i].tmax = rays[i].tmin;
  for (size_t i = 11; i < rays.size(); i += 89) rays[i].dir = Vec3{0.f, i % 2 ? 1.f : -1.f, 0.f};
  return rays;
}

// A fixed shuffle of 0..n-1 (indirect tracing).
std::vector<uint32_t> shuffled_order(size_t n) {
  std::vector<uint32_t> order(n);
  for (size_t i = 0; i < n; ++i) order[i] = static_cast<uint32_t>(i);
  for (size_t i = n; i > 1; --i) std::swap(order[i - 1], order[rng_u32(3, 0, static_cast<uint32_t>(i), 0) % i]);
  return order;
}

// Every field simt/simt.h defines outside the cache model.
void expect_same_step_counters(const CoherenceCounters& gpu, const CoherenceCounters& simt, const std::string& what) {
  SCOPED_TRACE(what);
  EXPECT_EQ(gpu.rays, simt.rays);
  EXPECT_EQ(gpu.warps, simt.warps);
  EXPECT_EQ(gpu.warp_size, simt.warp_size);
  EXPECT_EQ(gpu.line_bytes, simt.line_bytes);
  EXPECT_EQ(gpu.sector_bytes, simt.sector_bytes);
  EXPECT_EQ(gpu.node_steps, simt.node_steps);
  EXPECT_EQ(gpu.leaf_steps, simt.leaf_steps);
  EXPECT_EQ(gpu.triangle_steps, simt.triangle_steps);
  EXPECT_EQ(gpu.node_lanes, simt.node_lanes);
  EXPECT_EQ(gpu.leaf_lanes, simt.leaf_lanes);
  EXPECT_EQ(gpu.triangle_lanes, simt.triangle_lanes);
  EXPECT_EQ(gpu.node_lines, simt.node_lines);
  EXPECT_EQ(gpu.triangle_lines, simt.triangle_lines);
  EXPECT_EQ(gpu.node_fetches, simt.node_fetches);
  EXPECT_EQ(gpu.triangle_fetches, simt.triangle_fetches);
  EXPECT_EQ(gpu.nodes, simt.nodes);
  EXPECT_EQ(gpu.leaves, simt.leaves);
  EXPECT_EQ(gpu.triangles, simt.triangles);
}

std::string describe(const WarpStepCounters& w) {
  return "rays " + std::to_string(w.rays) + " steps " + std::to_string(w.node_steps) + "/" +
         std::to_string(w.leaf_steps) + "/" + std::to_string(w.triangle_steps) + " lanes " +
         std::to_string(w.node_lanes) + "/" + std::to_string(w.leaf_lanes) + "/" + std::to_string(w.triangle_lanes) +
         " lines " + std::to_string(w.node_lines) + "/" + std::to_string(w.triangle_lines) + " fetches " +
         std::to_string(w.node_fetches) + "/" + std::to_string(w.triangle_fetches) + " per ray " +
         std::to_string(w.nodes) + "/" + std::to_string(w.leaves) + "/" + std::to_string(w.triangles);
}

// The counting kernel against simt_trace_warp, warp by warp (lane i of the batch traces rays[order[i]]).
void expect_counting_matches_simt(const Bvh& bvh, const std::vector<Ray>& rays, const std::vector<uint32_t>* order,
                                  uint32_t line, const std::string& what) {
  SCOPED_TRACE(what + ", line " + std::to_string(line));
  const SimtConfig layout = simt_config(bvh.view(), 32, line, 32);

  std::vector<Ray> lanes = rays;
  if (order) {
    lanes.resize(order->size());
    for (size_t i = 0; i < order->size(); ++i) lanes[i] = rays[(*order)[i]];
  }
  cuda::DeviceTracer device(bvh.view());
  std::vector<Hit> gpu_hits(lanes.size());
  std::vector<WarpStepCounters> gpu_warps;
  device.trace_counting(rays.data(), order ? order->data() : nullptr, lanes.size(), gpu_hits.data(), layout, 128,
                        gpu_warps);
  EXPECT_GE(device.last_kernel_ms(), 0.f);

  const size_t warps = (lanes.size() + 31) / 32;
  ASSERT_EQ(gpu_warps.size(), warps);
  std::vector<Hit> simt_hits(lanes.size());
  const FlushDenormalsScope ftz;  // the CPU tracers' floating-point mode, which the traversal kernels share
  size_t differ = 0;
  for (size_t w = 0; w < warps; ++w) {
    const auto n = static_cast<uint32_t>(std::min<size_t>(32, lanes.size() - w * 32));
    CoherenceCounters c;
    simt_trace_warp(bvh.view(), lanes.data() + w * 32, n, layout, simt_hits.data() + w * 32, c);
    const WarpStepCounters& expected = c;
    if (std::memcmp(&expected, &gpu_warps[w], sizeof(expected)) != 0 && ++differ <= 3)
      ADD_FAILURE() << "warp " << w << ": gpu " << describe(gpu_warps[w]) << "\n      simt " << describe(expected);
  }
  EXPECT_EQ(differ, 0u) << differ << " of " << warps << " warps differ";
  EXPECT_EQ(differing_hits(gpu_hits, simt_hits), 0u);
}

// ---- registry and parameters (run with or without a GPU) ----

TEST(GpuTracerRegistry, ListedInCudaBuildsWithItsParameters) {
  const auto& infos = tracer_infos();
  const auto it = std::find_if(infos.begin(), infos.end(), [](const TracerInfo& i) { return i.name == "cuda"; });
  ASSERT_NE(it, infos.end());
  EXPECT_EQ(default_params(it->table()),
            "kernel=persistent,block=128,counters=off,line=64,bvh=bvh2,traversal=tuned,stack=local,pipeline=device");
  EXPECT_EQ(it->table()[2].choices, (std::vector<std::string>{"off", "on", "hw"}));
}

TEST(GpuTracerRegistry, BadParametersAndMissingDeviceAreClearErrors) {
  const Scene scene = load_scene("cornell");
  const Bvh bvh = build_bvh(scene);
  auto message = [&](const std::string& params) {
    try {
      make_tracer({"cuda", params}, scene, bvh);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message("block=100").find("multiple of 32"), std::string::npos);
  EXPECT_NE(message("block=2048").find("block"), std::string::npos);
  EXPECT_NE(message("kernel=fast").find("persistent"), std::string::npos);
  EXPECT_NE(message("warp=16").find("warp"), std::string::npos);
  EXPECT_NE(message("bvh=bvh4").find("cwbvh"), std::string::npos);
  EXPECT_NE(message("pipeline=gpu").find("device, fused, host"), std::string::npos) << message("pipeline=gpu");
  EXPECT_NE(message("bvh=cwbvh,counters=on").find("counters=on has no CWBVH kernel"), std::string::npos)
      << message("bvh=cwbvh,counters=on");
  EXPECT_NE(message("traversal=fast").find("tuned, classic"), std::string::npos) << message("traversal=fast");
  EXPECT_NE(message("bvh=cwbvh,traversal=classic").find("traversal=classic is a BVH2 kernel"), std::string::npos)
      << message("bvh=cwbvh,traversal=classic");
  EXPECT_NE(message("stack=shared").find("stack=shared is the CWBVH kernel's"), std::string::npos)
      << message("stack=shared");
  EXPECT_NE(message("stack=global").find("local, shared"), std::string::npos) << message("stack=global");
  if (cuda::device_count() == 0) {
    EXPECT_NE(message("").find("tracer 'cuda': no CUDA device"), std::string::npos) << message("");
  } else {
    EXPECT_EQ(message(""), "");
    auto t = make_tracer({"cuda", ""}, scene, bvh);
    EXPECT_EQ(t->params(),
              "kernel=persistent,block=128,counters=off,line=64,bvh=bvh2,traversal=tuned,stack=local,pipeline=device");
    EXPECT_EQ(t->last_counters(), nullptr);
    EXPECT_LT(t->last_device_ms(), 0.0);  // nothing traced yet
    auto c = make_tracer({"cuda", "counters=on,line=128"}, scene, bvh);
    ASSERT_NE(c->last_counters(), nullptr);  // a modelling tracer from the start, as the harness asks before tracing
  }
}

// ---- hits ----

TEST(GpuTracer, HitsEqualTheCpuTracerForEveryKernelBlockAndOrder) {
  SKIP_WITHOUT_GPU();
  for (const std::string& spec : scene_specs()) {
    SCOPED_TRACE(spec);
    const auto f = make_frame(spec);
    auto cpu = make_tracer({"cpu", ""}, f->scene, f->bvh);
    const std::vector<Ray> primary = f->primary.rays;
    const std::vector<Ray> secondary = stiff_batch(f->secondary);
    const std::vector<uint32_t> order = shuffled_order(secondary.size());
    const std::vector<Hit> cpu_primary = trace_with(*cpu, primary);
    const std::vector<Hit> cpu_secondary = trace_with(*cpu, secondary);
    const std::vector<Hit> cpu_indirect = trace_with(*cpu, secondary, &order);
    // Both BVH2 kernels (tuned, the default, and classic) with each launch shape.
    for (const char* params :
         {"kernel=persistent,block=128", "kernel=persistent,block=32", "kernel=persistent,block=1024",
          "kernel=simple,block=128", "kernel=simple,block=64", "kernel=simple,block=1024", "traversal=classic",
          "traversal=classic,block=1024", "traversal=classic,kernel=simple", "counters=on", "counters=on,block=1024"}) {
      SCOPED_TRACE(params);
      auto gpu = make_tracer({"cuda", params}, f->scene, f->bvh);
      EXPECT_EQ(differing_hits(trace_with(*gpu, primary), cpu_primary), 0u);
      EXPECT_GT(gpu->last_device_ms(), 0.0);
      EXPECT_EQ(differing_hits(trace_with(*gpu, secondary), cpu_secondary), 0u);
      EXPECT_EQ(differing_hits(trace_with(*gpu, secondary, &order), cpu_indirect), 0u);
      // The device buffers grow and shrink between calls: a short batch after a long one, then an empty one.
      const std::vector<Ray> few(secondary.begin(), secondary.begin() + 33);
      EXPECT_EQ(
          differing_hits(trace_with(*gpu, few), std::vector<Hit>(cpu_secondary.begin(), cpu_secondary.begin() + 33)),
          0u);
      EXPECT_TRUE(trace_with(*gpu, std::vector<Ray>{}).empty());
    }
  }
}

// The CWBVH kernels (core/traverse_cwbvh.h on the device): hits equal `cpu:bvh=cwbvh` bit for bit for every
// kernel, direct and indirect; against the BVH2 on the GPU the same t for every ray (bit for bit) and the same
// Hit wherever the prim is the same (another prim only at exactly the same t: a tie on a shared edge).
TEST(GpuTracer, CwbvhHitsEqualTheCpuCwbvhAndTheBvh2) {
  SKIP_WITHOUT_GPU();
  for (const std::string& spec : scene_specs()) {
    SCOPED_TRACE(spec);
    const auto f = make_frame(spec);
    auto cpu = make_tracer({"cpu", "bvh=cwbvh"}, f->scene, f->bvh);
    auto bvh2 = make_tracer({"cuda", ""}, f->scene, f->bvh);
    const std::vector<Ray> secondary = stiff_batch(f->secondary);
    const std::vector<uint32_t> order = shuffled_order(secondary.size());
    const std::vector<Hit> cpu_primary = trace_with(*cpu, f->primary.rays);
    const std::vector<Hit> cpu_secondary = trace_with(*cpu, secondary);
    const std::vector<Hit> cpu_indirect = trace_with(*cpu, secondary, &order);
    for (const char* params :
         {"bvh=cwbvh", "bvh=cwbvh,block=32", "bvh=cwbvh,kernel=simple,block=64", "bvh=cwbvh,block=1024",
          "bvh=cwbvh,stack=shared", "bvh=cwbvh,stack=shared,kernel=simple,block=64"}) {
      SCOPED_TRACE(params);
      auto gpu = make_tracer({"cuda", params}, f->scene, f->bvh);
      EXPECT_EQ(gpu->last_counters(), nullptr);
      EXPECT_EQ(differing_hits(trace_with(*gpu, f->primary.rays), cpu_primary), 0u);
      EXPECT_GT(gpu->last_device_ms(), 0.0);
      EXPECT_EQ(differing_hits(trace_with(*gpu, secondary), cpu_secondary), 0u);
      EXPECT_EQ(differing_hits(trace_with(*gpu, secondary, &order), cpu_indirect), 0u);
      EXPECT_TRUE(trace_with(*gpu, std::vector<Ray>{}).empty());
    }
    const std::vector<Hit> b = trace_with(*bvh2, secondary);
    size_t t_differ = 0, ties = 0, hit_differ = 0;
    for (size_t i = 0; i < b.size(); ++i) {
      const Hit& c = cpu_secondary[i];
      if (std::memcmp(&c.t, &b[i].t, sizeof(float)) != 0)
        ++t_differ;
      else if (c.prim != b[i].prim)
        ++ties;
      else if (std::memcmp(&c, &b[i], sizeof(Hit)) != 0)
        ++hit_differ;
    }
    EXPECT_EQ(t_differ, 0u);
    EXPECT_EQ(hit_differ, 0u);
    EXPECT_LE(ties, b.size() / 100) << ties << " ties of " << b.size();
  }
}

// The persistent kernel fetches whole warps from one counter: a batch much larger than the resident warps, with
// a length that is not a multiple of 32, must still be traced exactly once per ray. At the simulator size the
// batch is 1.5 times the resident threads (the simulated GPU's occupancy) instead of 1.5 M rays.
TEST(GpuTracer, PersistentKernelCoversLargeBatchesOnce) {
  SKIP_WITHOUT_GPU();
  const auto f = make_frame("cornell", test::gpu_test_size(640, 160), test::gpu_test_size(480, 120));
  auto cpu = make_tracer({"cpu", ""}, f->scene, f->bvh);
  cuda::DeviceTracer device(f->bvh.view());
  const size_t resident = static_cast<size_t>(device.persistent_blocks(cuda::TraceLaunch{})) * 128;
  const size_t count = test::gpu_test_size<size_t>(1500007, resident + resident / 2 + 7);
  std::vector<Ray> rays = f->secondary.rays;
  while (rays.size() < count) rays.insert(rays.end(), f->secondary.rays.begin(), f->secondary.rays.end());
  rays.resize(count);
  EXPECT_LT(resident, rays.size());
  std::vector<Hit> gpu(rays.size());  // a slot no warp fetched would keep whatever the fresh device buffer held
  device.trace(rays.data(), nullptr, rays.size(), gpu.data(), cuda::TraceLaunch{});
  EXPECT_EQ(differing_hits(gpu, trace_with(*cpu, rays)), 0u);
}

// ---- counters ----

TEST(GpuTracer, CountingKernelEqualsSimtWarpByWarp) {
  SKIP_WITHOUT_GPU();
  for (const std::string& spec : scene_specs()) {
    const auto f = make_frame(spec);
    const std::vector<Ray> secondary = stiff_batch(f->secondary);
    const std::vector<uint32_t> order = shuffled_order(secondary.size());
    for (uint32_t line : {64u, 128u}) {
      expect_counting_matches_simt(f->bvh, f->primary.rays, nullptr, line, spec + " primary");
      expect_counting_matches_simt(f->bvh, secondary, nullptr, line, spec + " noopt secondary");
      expect_counting_matches_simt(f->bvh, secondary, &order, line, spec + " noopt secondary, shuffled indirect");
    }
  }
}

// Through the registry: `cuda:counters=on` and `simt` report the same step, line, fetch and per-ray counters, for
// direct and indirect tracing; the cache-model fields are the simt tracer's alone.
TEST(GpuTracer, CudaCountersEqualTheSimtTracer) {
  SKIP_WITHOUT_GPU();
  for (const std::string& spec : scene_specs()) {
    const auto f = make_frame(spec);
    const std::vector<uint32_t> order = shuffled_order(f->secondary.size());
    for (const char* line : {"64", "128"}) {
      auto gpu = make_tracer({"cuda", std::string("counters=on,line=") + line}, f->scene, f->bvh);
      auto simt = make_tracer({"simt", std::string("line=") + line}, f->scene, f->bvh);
      const std::vector<Hit> g = trace_with(*gpu, f->secondary.rays), s = trace_with(*simt, f->secondary.rays);
      EXPECT_EQ(differing_hits(g, s), 0u);
      expect_same_step_counters(*gpu->last_counters(), *simt->last_counters(), spec + " line " + line);
      EXPECT_EQ(gpu->last_counters()->l1_hits + gpu->last_counters()->l1_misses, 0u);
      trace_with(*gpu, f->secondary.rays, &order);
      trace_with(*simt, f->secondary.rays, &order);
      expect_same_step_counters(*gpu->last_counters(), *simt->last_counters(), spec + " indirect line " + line);
    }
  }
}

}  // namespace
}  // namespace raycoh
