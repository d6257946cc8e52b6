// The timing model of the `simt` tracer (simt/timed_replay.h) on hand-made step traces and on real batches: a
// timeline computed by hand, the invariants a timing model must keep (more bandwidth or more resident warps never
// slow it, an L1-resident BVH is bound by issue and L1, not by misses), warps placed as the CUDA launch places
// them, pausing and resuming, occupancy, and the pipeline stages around the trace.
#include <gtest/gtest.h>

#include <numeric>
#include <random>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "generators/pixel_order.h"
#include "generators/primary.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "simt/gpu_model.h"
#include "simt/pipeline_model.h"
#include "simt/timed_replay.h"
#include "tests/test_util.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

// One SM with `resident` slots, unit-rate ports and round latencies, so that timelines can be worked by hand:
// 1 GHz, one 32-byte sector per cycle through the L2 and the DRAM ports, latencies 10 / 100 / 300 cycles.
// The timelines are worked with the classic BVH2 kernel's step costs (14 loads, 18 local accesses per node step).
GpuModelConfig hand_config(uint32_t sms = 1, uint32_t resident = 1) {
  GpuModelConfig c = gpu_preset("rtx3060");
  use_kernel(c, TraceKernelChoice::Bvh2Classic);
  c.cache.sms = sms;
  c.cache.l1 = {4 * 128 * 2, 2};
  c.cache.l2 = {16 * 128 * 4, 4};
  c.gpu.clock_mhz = 1000;
  c.gpu.l2_bytes_per_clk = 32;
  c.gpu.dram_gb_s = 32;  // 32 bytes per cycle at 1 GHz
  c.gpu.l1_latency = 10;
  c.gpu.l2_latency = 100;
  c.gpu.dram_latency = 300;
  c.gpu.max_warps_per_sm = resident;
  c.kernel.block_threads = 32;
  return c;
}

WarpTrace node_steps(uint32_t lanes, const std::vector<std::vector<uint32_t>>& steps) {
  WarpTrace t;
  t.lanes = lanes;
  for (const auto& s : steps) {
    std::vector<uint64_t> sectors(s.begin(), s.end());
    t.add_step(SimtStepKind::Node, sectors.data(), static_cast<uint32_t>(sectors.size()));
  }
  return t;
}

ModeledKernel replay(const GpuModelConfig& c, std::vector<WarpTrace> traces, uint64_t ray_base = 1 << 20) {
  TimedReplay r(c, traces.size(), ray_base);
  r.run(traces, traces.size());
  EXPECT_TRUE(r.done());
  return r.result();
}

TEST(TimingModel, OneWarpTimelineByHand) {
  // Fetch: 28 issue cycles; two 16-byte loads of 32 lanes = 2 x 4 L1 cycles; 32 ray sectors, all cold: through
  // the L2 port at cycles 8..39 and the DRAM port at 8..39, the last arriving at 39 + 300; then 28 cycles of
  // traversal_begin: ready at 367. Node step: 115 issue cycles (the port is free), 14 loads x 1 line + 18 local
  // accesses = 32 L1 cycles (367..399), sectors 0 and 1 cold: L2 port at 399 and 400, DRAM at 399 and 400,
  // arriving 700; plus 115 cycles: the warp ends at 815.
  const GpuModelConfig c = hand_config();
  const ModeledKernel k = replay(c, {node_steps(32, {{0, 1}})});
  EXPECT_DOUBLE_EQ(k.cycles, 815.0);
  EXPECT_DOUBLE_EQ(k.ms, 815.0 / 1e6);
  EXPECT_EQ(k.resident_warps, 1u);
  EXPECT_EQ(k.ray_sectors, 32u);
  EXPECT_EQ(k.ray_dram_sectors, 32u);
  EXPECT_DOUBLE_EQ(k.issue_cycles, 28.0 + 115.0);
  // In-order issue (the gpgpusim-rtx3070 preset's PTX): after its data the node step takes its in-order time less
  // the one L1 hit (10 cycles) that time assumed, 500 - 10 = 490 instead of 115; the issue port's share is unchanged.
  GpuModelConfig in_order = c;
  in_order.kernel.node.inorder_cycles = 500;
  const ModeledKernel o = replay(in_order, {node_steps(32, {{0, 1}})});
  EXPECT_DOUBLE_EQ(o.cycles, 815.0 - 115.0 + 490.0);
  EXPECT_DOUBLE_EQ(o.issue_cycles, k.issue_cycles);
  in_order.kernel.node.inorder_cycles = 100;  // shorter than the back-to-back issue: no effect
  EXPECT_DOUBLE_EQ(replay(in_order, {node_steps(32, {{0, 1}})}).cycles, 815.0);
}

TEST(TimingModel, DivergentLoadsTakeMoreL1Wavefronts) {
  // The same step touching 1 line or 16 lines (4 tags per cycle): 14 loads x 1 vs 14 x 4 wavefronts.
  const GpuModelConfig c = hand_config();
  std::vector<uint32_t> one_line = {0, 1}, sixteen_lines;
  for (uint32_t l = 0; l < 16; ++l) sixteen_lines.push_back(l * 4);
  const ModeledKernel a = replay(c, {node_steps(32, {one_line})});
  const ModeledKernel b = replay(c, {node_steps(32, {sixteen_lines})});
  EXPECT_DOUBLE_EQ(a.l1_busy, 8 + 14 * 1 + 18);
  EXPECT_DOUBLE_EQ(b.l1_busy, 8 + 14 * 4 + 18);
  EXPECT_GT(b.cycles, a.cycles);
  // One warp on one SM: the GPU-wide wavefront count is that SM's busy time; 18 of them local (the stack).
  EXPECT_DOUBLE_EQ(b.l1_wavefronts, b.l1_busy);
  EXPECT_DOUBLE_EQ(b.l1_local_wavefronts, 18);
  // A tag stage of 1 line per cycle takes 16 wavefronts per load; one of 16 lines, a single wavefront.
  GpuModelConfig one = c, sixteen = c;
  one.gpu.l1_tags_per_clk = 1;
  sixteen.gpu.l1_tags_per_clk = 16;
  EXPECT_DOUBLE_EQ(replay(one, {node_steps(32, {sixteen_lines})}).l1_busy, 8 + 14 * 16 + 18);
  EXPECT_DOUBLE_EQ(replay(sixteen, {node_steps(32, {sixteen_lines})}).l1_busy, 8 + 14 * 1 + 18);
}

std::vector<WarpTrace> random_traces(size_t warps, uint32_t footprint_sectors, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<WarpTrace> traces;
  for (size_t w = 0; w < warps; ++w) {
    WarpTrace t;
    t.lanes = 32;
    const uint32_t steps = 1 + rng() % 20;
    for (uint32_t s = 0; s < steps; ++s) {
      const auto kind = static_cast<SimtStepKind>(rng() % 3);
      std::vector<uint64_t> sectors;
      if (kind != SimtStepKind::Leaf) {
        const uint32_t n = 1 + rng() % 24;
        for (uint32_t i = 0; i < n; ++i) sectors.push_back(rng() % footprint_sectors);
        std::sort(sectors.begin(), sectors.end());
        sectors.erase(std::unique(sectors.begin(), sectors.end()), sectors.end());
      }
      t.add_step(kind, sectors.data(), static_cast<uint32_t>(sectors.size()));
    }
    traces.push_back(std::move(t));
  }
  return traces;
}

TEST(TimingModel, MoreBandwidthNeverSlowsIt) {
  // Up to a list-scheduling anomaly (Graham, 1969): a faster port can change which warps finish last, which may
  // lengthen the tail by a fraction of one warp's duration: below 0.5% here. Starting from a port slow enough
  // to be the bottleneck, doubling its bandwidth must help a lot.
  const auto traces = random_traces(400, 20000, 3);
  for (const bool l2 : {false, true}) {
    GpuModelConfig c = hand_config(4, 8);
    (l2 ? c.gpu.l2_bytes_per_clk : c.gpu.dram_gb_s) = 4;
    const double first = replay(c, traces).cycles;
    double last = first;
    for (int i = 0; i < 4; ++i) {
      (l2 ? c.gpu.l2_bytes_per_clk : c.gpu.dram_gb_s) *= 2;
      const double t = replay(c, traces).cycles;
      EXPECT_LE(t, last * 1.005) << (l2 ? "L2" : "DRAM") << " bandwidth x" << (2 << i);
      last = std::min(last, t);
    }
    EXPECT_LT(last, 0.5 * first) << (l2 ? "L2" : "DRAM") << " was the bottleneck";
  }
}

TEST(TimingModel, MoreResidentWarpsNeverSlowALatencyBoundCase) {
  // Long DRAM latency, a footprint far beyond the caches: each warp mostly waits, others fill the gaps.
  const auto traces = random_traces(512, 1 << 20, 5);
  GpuModelConfig c = hand_config(2, 64);
  c.gpu.dram_latency = 2000;
  c.gpu.dram_gb_s = 1e4;
  c.gpu.l2_bytes_per_clk = 1e4;
  double last = 1e300;
  for (uint32_t resident : {1u, 2u, 4u, 8u, 16u, 32u}) {
    c.resident_override = resident;
    const ModeledKernel k = replay(c, traces);
    EXPECT_EQ(k.resident_warps, resident);
    EXPECT_LE(k.cycles, last) << resident << " resident warps";
    last = k.cycles;
  }
}

TEST(TimingModel, PausingAndResumingGivesTheSameResult) {
  for (const TraceKernel kind : {TraceKernel::Persistent, TraceKernel::Simple}) {
    GpuModelConfig c = hand_config(3, 8);
    c.kernel.kind = kind;
    c.kernel.block_threads = 64;  // simple kernel: blocks of two warps
    const auto original = random_traces(157, 3000, 9);
    const ModeledKernel one = replay(c, original);
    std::vector<WarpTrace> pieces = original;
    TimedReplay resumed(c, pieces.size(), 1 << 20);
    std::mt19937 rng(3);
    for (size_t ready = 0; !resumed.done();) {
      ready = std::min(pieces.size(), ready + rng() % 9);
      resumed.run(pieces, ready);
    }
    const ModeledKernel two = resumed.result();
    EXPECT_EQ(one.cycles, two.cycles) << to_string(kind);
    EXPECT_EQ(one.l1_busy, two.l1_busy);
    EXPECT_EQ(one.dram_busy, two.dram_busy);
    for (const WarpTrace& t : pieces) EXPECT_EQ(t.requests(), 0u) << "finished traces are freed";
  }
}

TEST(TimingModel, BlocksOfTheSimpleKernelStayOnOneSm) {
  // Block size decides which warps share an SM, as the CUDA launch does: a block's warps start together on one
  // SM; persistent warps are dealt one by one.
  GpuModelConfig c = hand_config(4, 8);
  c.kernel.kind = TraceKernel::Simple;
  c.kernel.block_threads = 128;
  std::vector<WarpTrace> traces = random_traces(64, 3000, 11);
  TimedReplay r(c, traces.size(), 1 << 20);
  r.run(traces, traces.size());
  const std::vector<uint32_t>& sm = r.warp_sms();
  for (size_t w = 0; w < traces.size(); ++w) EXPECT_EQ(sm[w], sm[w / 4 * 4]) << "warp " << w;
  EXPECT_NE(sm[0], sm[4]) << "the first wave deals blocks to different SMs";

  c.kernel.kind = TraceKernel::Persistent;
  traces = random_traces(64, 3000, 11);
  TimedReplay p(c, traces.size(), 1 << 20);
  p.run(traces, traces.size());
  for (uint32_t w = 0; w < 4; ++w) EXPECT_EQ(p.warp_sms()[w], w) << "the first wave deals warps to SMs in turn";
}

TEST(TimingModel, EmptyBatchIsDone) {
  std::vector<WarpTrace> none;
  TimedReplay r(hand_config(), 0, 0);
  EXPECT_TRUE(r.done());
  r.run(none, 0);
  EXPECT_EQ(r.result().cycles, 0.0);
}

TEST(TimingModel, OccupancyFollowsTheCudaRules) {
  GpuModelConfig c = gpu_preset("rtx3060");
  // 55 registers: 1792 per warp (allocation unit 256), 36 warps by registers, in whole blocks of 4.
  EXPECT_EQ(resident_warps(c), 36u);
  c.kernel.regs_per_thread = 32;
  EXPECT_EQ(resident_warps(c), 48u);  // the SM's warp limit (CC 8.6)
  c.kernel.block_threads = 32;
  EXPECT_EQ(resident_warps(c), 16u);  // the SM's block limit
  GpuModelConfig h = gpu_preset("h100");
  EXPECT_EQ(resident_warps(h), 36u);
  h.kernel.regs_per_thread = 32;
  EXPECT_EQ(resident_warps(h), 64u);
  h.kernel.regs_per_thread = 255;
  h.kernel.block_threads = 1024;
  EXPECT_NE(test::error_of([&] { resident_warps(h); }).find("does not fit"), std::string::npos);
}

TEST(TimingModel, PresetsAndErrors) {
  const GpuModelConfig a = gpu_preset("rtx3060");
  EXPECT_EQ(a.cache.sms, 28u);
  EXPECT_EQ(a.cache.l1.bytes, 128u * 1024);
  EXPECT_EQ(a.cache.l2.bytes, 3u * 1024 * 1024);
  EXPECT_EQ(a.cache.line_bytes, 128u);
  EXPECT_EQ(a.cache.sector_bytes, 32u);
  EXPECT_DOUBLE_EQ(a.gpu.dram_gb_s, 360.0);
  EXPECT_EQ(SectoredLruCache(a.cache.l1.bytes, a.cache.l1.ways, 128, 32).sets(), 4u);
  EXPECT_EQ(SectoredLruCache(a.cache.l2.bytes, a.cache.l2.ways, 128, 32).sets(), 1536u);
  const GpuModelConfig h = gpu_preset("h100");
  EXPECT_EQ(h.cache.sms, 132u);
  EXPECT_EQ(h.cache.l2.bytes, 50u * 1024 * 1024);
  EXPECT_NO_THROW(validate(a));
  EXPECT_NO_THROW(validate(h));
  EXPECT_NE(test::error_of([] { gpu_preset("rtx4090"); }).find("rtx3060, h100, gpgpusim-rtx3070"), std::string::npos);
  GpuModelConfig bad = a;
  bad.gpu.dram_gb_s = 0;
  EXPECT_THROW(validate(bad), Error);
  bad = a;
  bad.gpu.l2_latency = 10;  // below the L1's
  EXPECT_THROW(validate(bad), Error);
  bad = a;
  bad.kernel.block_threads = 48;
  EXPECT_THROW(validate(bad), Error);
}

// ---- on real batches -------------------------------------------------------------------------------------

struct Frame {
  Scene scene;
  Bvh bvh;
  std::vector<Ray> rays;
};

Frame primary_frame(const std::string& scene, int w, int h) {
  Frame f;
  f.scene = load_scene(scene);
  f.bvh = build_bvh(f.scene);
  const PixelRays p = make_primary_rays(f.scene.camera, w, h, make_pixel_order(w, h, RayOrder::Tile, 8, 8), 1, 0, true);
  f.rays = p.rays;
  return f;
}

CoherenceCounters trace_simt(const Frame& f, const std::vector<Ray>& rays, const std::string& params) {
  auto simt = make_tracer({"simt", params}, f.scene, f.bvh);
  std::vector<Hit> hits(rays.size());
  simt->trace(rays.data(), rays.size(), hits.data());
  return *simt->last_counters();
}

TEST(TimingModel, IdenticalRaysReachTheCoherentBound) {
  // A warp of identical rays has every lane on one path: one line per load, no idle lane. Per traversal step it
  // is the model's coherent bound: no batch of the same scene's rays is faster per step. One SM full of warps,
  // so that throughput, not the launch's first wave, decides.
  // Per step, its time holds for the classic kernel, whose steps dwarf the per-warp ray fetch (8 wavefronts under
  // the rtx3060 tag rule: two 16-byte loads of 32 lanes). With the tuned kernel's cheap steps the fetch, the same
  // in both batches (as many full warps), weighs more per step where warps take fewer steps: the L1 bound holds
  // for the steps' own wavefronts.
  const Frame f = primary_frame("voxels", 128, 96);
  const std::vector<Ray> same(f.rays.size(), f.rays[f.rays.size() / 2 + 7]);
  for (const std::string kernel : {"traversal=classic", "traversal=tuned"}) {
    SCOPED_TRACE(kernel);
    const CoherenceCounters s = trace_simt(f, same, "sms=1," + kernel);
    const CoherenceCounters p = trace_simt(f, f.rays, "sms=1," + kernel);
    EXPECT_DOUBLE_EQ(s.simt_efficiency(), 1.0);
    ASSERT_EQ(s.warps, p.warps);
    const double steps_s = double(s.node_steps + s.leaf_steps + s.triangle_steps);
    const double steps_p = double(p.node_steps + p.leaf_steps + p.triangle_steps);
    const double fetch = 8.0 * double(s.warps);
    EXPECT_LE((s.modeled.l1_busy - fetch) / steps_s, (p.modeled.l1_busy - fetch) / steps_p);
    if (kernel == "traversal=classic") {
      EXPECT_LE(s.modeled.cycles / steps_s, p.modeled.cycles / steps_p);
      EXPECT_LE(s.modeled.l1_busy / steps_s, p.modeled.l1_busy / steps_p);
    }
  }
}

TEST(TimingModel, AnL1ResidentBvhIsNotBoundByMisses) {
  // Cornell's BVH fits an L1: faster L2 and DRAM change (almost) nothing; the issue port and the L1 pipeline
  // bound the time.
  const Frame f = primary_frame("cornell", 256, 192);
  const CoherenceCounters base = trace_simt(f, f.rays, "sms=1");
  const CoherenceCounters fast = trace_simt(f, f.rays, "sms=1,dram_gbs=3600,l2_bpc=13000");
  EXPECT_LT(double(base.l2_misses + base.l2_hits), 0.02 * double(base.l1_hits));
  EXPECT_NEAR(fast.modeled.cycles, base.modeled.cycles, 0.02 * base.modeled.cycles);
  EXPECT_GT(std::max(base.modeled.issue_busy, base.modeled.l1_busy), 0.7 * base.modeled.cycles);
}

TEST(TimingModel, PipelineStagesMoveTheDocumentedBytes) {
  const size_t n = 1 << 20;
  // Onesweep, 32-bit keys: a histogram pass reading 4 bytes, then four passes reading and writing 8 bytes.
  EXPECT_DOUBLE_EQ(sort_bytes(n, 32), n * (4.0 + 4 * 16.0));
  EXPECT_DOUBLE_EQ(sort_bytes(n, 64), n * (8.0 + 8 * 24.0));
  EXPECT_EQ(sort_bytes(n, 0), 0.0);
  EXPECT_DOUBLE_EQ(key_bytes(n, 32), n * (32.0 + 4 + 4));
  // A gather through the identity reads each array's sectors once; a scattered one reads a sector per element.
  std::vector<uint32_t> identity(n), scattered(n);
  std::iota(identity.begin(), identity.end(), 0u);
  for (size_t i = 0; i < n; ++i) scattered[i] = static_cast<uint32_t>((i * 2654435761u) % n);
  const double contiguous = permute_bytes(identity.data(), n);
  EXPECT_NEAR(contiguous, 2.0 * n * batch_bytes_per_ray(), 0.05 * contiguous);
  EXPECT_GT(permute_bytes(scattered.data(), n), 2.0 * contiguous);
  EXPECT_GT(modeled_generation_ms(gpu_preset("rtx3060"), n, n), 0.0);
}

}  // namespace
}  // namespace raycoh
