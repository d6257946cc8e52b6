// Tracer `cuda`: our traversal (core/traverse.h) on the GPU over the shared flat BVH2 (cuda/trace_kernels.h).
// The BVH is uploaded once when the tracer is made; each trace() uploads the rays (and, for trace_indirect, the
// order: lane i traces rays[order[i]] on the device), runs one kernel and downloads the hits. Its hits equal the
// `cpu` tracer's bit for bit.
//
// Timing runs carry no counter code: last_device_ms() is the kernel time of the last call, from CUDA events
// (transfers excluded); the harness takes the median over repeated calls after a warm-up, as for every timing
// tracer. Counting runs (counters=on) run the warp-synchronous counting kernel instead, which follows simt/simt.h
// rule by rule: last_counters() then holds the same warp-step, lane, line, fetch and per-ray fields as the `simt`
// tracer with the same `line` (warp 32, 32-byte sectors), for the same rays in the same order. The cache-model
// fields (l1_*, l2_*, dram_bytes, modeled) are not produced on the GPU and stay 0: they come from `simt`.
//
// Parameters: cuda_params() below. The persistent kernel's warps fetch 32 consecutive rays at a time from a
// global atomic counter (Aila & Laine 2009); the simple one runs one thread per ray. `bvh=cwbvh` traces the
// compressed 8-wide BVH instead (core/traverse_cwbvh.h, built here from the scene by bvh/cwbvh_build.h, not timed,
// as the cpu and simt tracers do): same kernels, hits equal `cpu:bvh=cwbvh`'s; it has no counting kernel.
//
// pipeline=device (the default): a run makes every batch on the GPU too (cuda/device_pipeline.h): camera rays,
// the noopt / ours / contiguous generators, every key encoder, CUB's radix sort, the gather and the trace, each
// timed with CUDA events; the harness reads those times through device_pipeline() instead of timing trace()
// calls. pipeline=fused does the same except that each secondary pass is one kernel that makes every tile's rays
// and traces them where they are made (cuda/fused_kernels.cu; no batch in memory, no encoder). pipeline=host
// traces the batches the host made, the ones every other tracer traces.
//
// Sources: Aila & Laine, "Understanding the Efficiency of Ray Traversal on GPUs" (HPG 2009): while-while
// traversal, persistent threads, two-boxes-per-node BVH2; Woop, Benthin & Wald (JCGT 2013): watertight triangles;
// Ylitie, Karras & Laine, "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs" (HPG 2017).
//
// counters=hw: the timing kernels (not the counting kernel) run under CUPTI's range profiler (cuda/hw_profiler.h):
// every trace() call, and every device pass (primary, secondary), is one profiling session whose trace kernels'
// hardware counters last_hw_counters() then holds, measured. CUPTI replays each kernel once per pass its metrics
// need, so the rows' times are not timings: run_under() says "cupti-counters" and the harness runs the tracer once
// per row, like a counting tracer. Where CUPTI cannot read counters (no library, GPGPU-Sim, a driver restricting
// profiling to administrators) one line says why and the tracer is the plain timing tracer.
//
// Scenes with alpha MASK cut-outs (Scene::alpha): the mask arrays are uploaded once with the BVH and every kernel
// (persistent, simple, counting; BVH2 and CWBVH) runs the AlphaTest any-hit filter of core/alpha_mask.h, the same
// test as the cpu, simt and embree tracers, so hits still equal the `cpu` tracer's bit for bit. Scenes without
// masks run the NoAlphaTest kernels (the code that ran before). The counting kernel's counters count traversal
// steps and BVH fetches only; texel reads are not counted (as in simt).
#include "cuda/cuda_tracer.h"

#include <fmt/format.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "bvh/cwbvh_build.h"
#include "core/error.h"
#include "cuda/cuda_device.h"
#include "cuda/device_path_tracer.h"
#include "cuda/device_pipeline.h"
#include "cuda/hw_profiler.h"
#include "cuda/trace_kernels.h"
#include "scenes/scene.h"
#include "simt/simt.h"
#include "tracers/device_pipeline.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

// A device pipeline whose passes each run as one profiling session; the trace kernels' counters go to *counters.
class ProfiledPipeline final : public DevicePipeline {
 public:
  ProfiledPipeline(std::unique_ptr<DevicePipeline> inner, cuda::HwProfiler& profiler,
                   std::optional<HwCounters>& counters)
      : inner_(std::move(inner)), profiler_(profiler), counters_(counters) {}
  std::string refusal(const std::string& name, const Generator& generator, const Encoder& encoder) const override {
    return inner_->refusal(name, generator, encoder);
  }
  DeviceStageTimes primary(int width, int height, int tile_w, int tile_h, uint32_t seed, uint32_t frame,
                           bool jitter) override {
    profiler_.begin();
    const DeviceStageTimes t = inner_->primary(width, height, tile_w, tile_h, seed, frame, jitter);
    counters_ = profiler_.end();
    return t;
  }
  void first_hits_gbuffer() override { inner_->first_hits_gbuffer(); }
  GBuffer download_gbuffer() const override { return inner_->download_gbuffer(); }
  DeviceStageTimes secondary(const Generator& generator, const Encoder& encoder, PermuteMode mode, uint32_t seed,
                             GenerationStats& stats) override {
    profiler_.begin();
    const DeviceStageTimes t = inner_->secondary(generator, encoder, mode, seed, stats);
    counters_ = profiler_.end();
    return t;
  }
  void download_primary(PixelRays& rays, std::vector<Hit>& hits) const override {
    inner_->download_primary(rays, hits);
  }
  void download_secondary(RayBatch& generated, std::vector<uint32_t>& order, RayBatch& permuted,
                          std::vector<Hit>& hits) const override {
    inner_->download_secondary(generated, order, permuted, hits);
  }

 private:
  std::unique_ptr<DevicePipeline> inner_;
  cuda::HwProfiler& profiler_;
  std::optional<HwCounters>& counters_;
};

class CudaTracer final : public Tracer, public HwCounterSource {
 public:
  CudaTracer(std::unique_ptr<cuda::DeviceTracer> device, const cuda::TraceLaunch& launch, bool counting,
             const SimtConfig& layout, bool cwbvh, std::string params)
      : device_(std::move(device)),
        launch_(launch),
        counting_(counting),
        layout_(layout),
        cwbvh_(cwbvh),
        params_(std::move(params)) {
    counters_.warp_size = 32;
    counters_.line_bytes = layout_.line_bytes;
    counters_.sector_bytes = layout_.sector_bytes;
  }

  // pipeline=device: every batch is made, sorted and traced on the device (cuda/device_pipeline.h).
  void make_pipeline(const Scene& scene, const Bvh& bvh, bool fused) {
    cuda::PipelineTrace trace;
    trace.fused = fused;
    trace.tracer = device_.get();
    trace.launch = launch_;
    trace.counting = counting_;
    trace.layout = layout_;
    trace.counted = [this](const std::vector<WarpStepCounters>& warps, size_t rays) { count(warps, rays); };
    pipeline_ = cuda::make_device_pipeline(scene, bvh, std::move(trace));
    if (hw_) pipeline_ = std::make_unique<ProfiledPipeline>(std::move(pipeline_), *hw_, hw_counters_);
  }

  // counters=hw: CUPTI set up on the device's context (made by the upload); without counters, a timing tracer.
  void make_hw_profiler() {
    hw_ = std::make_unique<cuda::HwProfiler>();
    if (!hw_->unavailable().empty()) hw_.reset();
  }

  void trace(const Ray* rays, size_t count, Hit* hits) override { run(rays, nullptr, count, hits); }
  void trace_indirect(const Ray* rays, const uint32_t* order, size_t count, Hit* hits) override {
    run(rays, order, count, hits);
  }
  std::string params() const override { return params_; }
  std::string bvh_layout() const override { return cwbvh_ ? "cwbvh" : "bvh2"; }
  const CoherenceCounters* last_counters() const override { return counting_ ? &counters_ : nullptr; }
  double last_device_ms() const override { return device_->last_kernel_ms(); }
  DevicePipeline* device_pipeline() override { return pipeline_.get(); }
  const HwCounters* last_hw_counters() const override { return hw_counters_ ? &*hw_counters_ : nullptr; }
  std::string run_under() const override { return hw_ ? kHwCountersRunUnder : ""; }

 private:
  void run(const Ray* rays, const uint32_t* order, size_t count, Hit* hits) {
    if (!counting_) {
      if (hw_) hw_->begin();
      device_->trace(rays, order, count, hits, launch_);
      if (hw_) hw_counters_ = hw_->end();
      return;
    }
    device_->trace_counting(rays, order, count, hits, layout_, launch_.block, warps_);
    this->count(warps_, count);
  }

  // The counting kernel's warps summed into last_counters().
  void count(const std::vector<WarpStepCounters>& warps, size_t count) {
    CoherenceCounters total;
    total.warp_size = 32;
    total.line_bytes = layout_.line_bytes;
    total.sector_bytes = layout_.sector_bytes;
    for (const WarpStepCounters& w : warps) total.add(w);
    RAYCOH_CHECK(total.rays == count, fmt::format("the counting kernel saw {} rays of {}", total.rays, count));
    RAYCOH_CHECK(
        total.nodes == total.node_lanes && total.leaves == total.leaf_lanes && total.triangles == total.triangle_lanes,
        fmt::format("per-ray totals {}/{}/{} differ from the lane sums {}/{}/{}", total.nodes, total.leaves,
                    total.triangles, total.node_lanes, total.leaf_lanes, total.triangle_lanes));
    counters_ = total;
  }

  std::unique_ptr<cuda::DeviceTracer> device_;
  cuda::TraceLaunch launch_;
  bool counting_;
  SimtConfig layout_;
  bool cwbvh_;
  std::string params_;
  std::vector<WarpStepCounters> warps_;
  CoherenceCounters counters_;
  std::unique_ptr<cuda::HwProfiler> hw_;  // counters=hw where CUPTI reads counters
  std::optional<HwCounters> hw_counters_;
  std::unique_ptr<DevicePipeline> pipeline_;
};

}  // namespace

const ParamTable& cuda_params() {
  static const ParamTable table = {
      choice_param("kernel", "persistent", {"persistent", "simple"}, "persistent threads, or one thread per ray"),
      int_param("block", 128, 32, 1024, "threads per block, a multiple of 32"),
      choice_param("counters", "off", {"off", "on", "hw"},
                   "on: the counting kernel (its time is not a traversal time); hw: the GPU's own counters through "
                   "CUPTI (kernels replayed: rows run_under=cupti-counters, not timings)"),
      choice_param("line", "64", {"64", "128"}, "bytes per line of the counted transactions (simt's line)"),
      choice_param("bvh", "bvh2", {"bvh2", "cwbvh"},
                   "layout: the BVH2, or the compressed 8-wide BVH (Ylitie et al. 2017; no counting kernel)"),
      choice_param("traversal", "tuned", {"tuned", "classic"},
                   "BVH2 kernel: tuned (16-byte loads, state in registers) or classic (a 4-byte load per field, state "
                   "in local memory: the kernel until 2026-11, the baseline); bvh2 only"),
      choice_param("stack", "local", {"local", "shared"},
                   "CWBVH kernel's traversal stack: local memory, or shared memory sized by the tree's depth "
                   "(bvh=cwbvh only)"),
      choice_param("pipeline", "device", {"device", "fused", "host"},
                   "device: generate, key, sort, permute and trace on the GPU; fused: one kernel makes each tile's "
                   "secondary rays and traces them (every device generator; no batch, no encoder); host: trace "
                   "host-made batches"),
  };
  return table;
}

std::unique_ptr<Tracer> make_cuda_tracer(ParamSet& params, const Scene& scene, const Bvh& bvh) {
  cuda::TraceLaunch launch;
  launch.kernel =
      params.get_choice("kernel") == "persistent" ? cuda::TraceKernel::Persistent : cuda::TraceKernel::Simple;
  launch.block = params.get_int("block");
  if (launch.block % 32 != 0)
    throw Error(
        fmt::format("{}: block={} is not a multiple of 32 (a block holds whole warps)", params.owner(), launch.block));
  const std::string counters = params.get_choice("counters");
  const bool counting = counters == "on", hw = counters == "hw";
  const uint32_t line = static_cast<uint32_t>(std::stoi(params.get_choice("line")));
  const bool cwbvh = params.get_choice("bvh") == "cwbvh";
  launch.traversal =
      params.get_choice("traversal") == "classic" ? cuda::Bvh2Traversal::Classic : cuda::Bvh2Traversal::Tuned;
  launch.shared_stack = params.get_choice("stack") == "shared";
  const std::string choice = cuda::launch_choice_error(launch, cwbvh);
  if (!choice.empty()) throw Error(fmt::format("{}: {}", params.owner(), choice));
  const std::string pipeline = params.get_choice("pipeline");
  const bool on_device = pipeline != "host", fused = pipeline == "fused";
  params.finish();
  if (fused && counting)
    throw Error(
        fmt::format("{}: counters=on traces a batch with the counting kernel; pipeline=fused has none "
                    "(use pipeline=device)",
                    params.owner()));
  if (fused && launch.shared_stack)
    throw Error(
        fmt::format("{}: stack=shared gives the block's shared memory to the stack; pipeline=fused needs it "
                    "for the tile's rays (use stack=local)",
                    params.owner()));
  if (cwbvh && counting)
    throw Error(fmt::format("{}: counters=on has no CWBVH kernel (bvh=cwbvh); count CWBVH steps with the simt tracer",
                            params.owner()));
  if (cuda::device_count() == 0)
    throw Error(
        fmt::format("{}: no CUDA device (this machine has no usable GPU); use the cpu or simt tracer", params.owner()));
  // The addresses the simt tracer counts with, so that lines and sectors are the same units (32-byte sectors as
  // in both cache presets).
  const SimtConfig layout = simt_config(bvh.view(), 32, line, 32);
  // Alpha MASK arrays (empty when the scene has none), uploaded with the BVH.
  const cuda::AlphaMaskArrays alpha = cuda::scene_alpha_arrays(scene);
  // The CWBVH's host copy is dropped once uploaded.
  std::unique_ptr<cuda::DeviceTracer> device;
  if (cwbvh) {
    const Cwbvh cw = build_cwbvh(scene, bvh.config);
    device = std::make_unique<cuda::DeviceTracer>(cw.view(), alpha, static_cast<uint32_t>(cw.stats.max_depth));
  } else {
    device = std::make_unique<cuda::DeviceTracer>(bvh.view(), alpha);
  }
  device->check_launch(launch);
  auto tracer = std::make_unique<CudaTracer>(std::move(device), launch, counting, layout, cwbvh, params.canonical());
  if (hw) tracer->make_hw_profiler();
  if (on_device) tracer->make_pipeline(scene, bvh, fused);
  return tracer;
}

}  // namespace raycoh
