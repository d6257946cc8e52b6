// Tracer `simt`: a CPU model of a GPU running our traversal kernel. Warps of consecutive rays of the batch run the
// while-while traversal in lock step (simt/simt.h; the stepping and counting rules in docs/simt-model.md), and
// the warps' steps are replayed by the timing model (simt/timed_replay.h) on a modelled GPU: the cache model
// (simt/cache_model.h) says where each sector was found, the event simulation how long the kernel takes.
// Its hits equal the `cpu` tracer's bit for bit; its products are the CoherenceCounters of last_counters(),
// with the modeled kernel time, never its own wall-clock time. Alpha MASK cut-outs are honoured as the `cpu`
// tracer honours them (core/alpha_mask.h), but their texel reads are not modeled: on a masked scene the modeled
// memory traffic covers the BVH only.
//
// Parameters: simt_params() below. Rows whose default is "preset" take the preset's value (simt/gpu_presets.cpp);
// they exist for what-if studies (a GPU with half the DRAM bandwidth, another occupancy).
//
// Determinism and speed: everything depends on the batch and its order only, never on the thread count. Warps are
// traced in parallel with oneTBB, a chunk at a time, each producing its step trace; the timing model replays the
// traces in its event order on one thread, overlapped with tracing the next chunk. Sources: Aila & Laine, HPG 2009
// (while-while traversal, persistent threads, speculative node walk); the presets' sources in
// simt/gpu_presets.cpp.
#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "bvh/bvh_build.h"
#include "bvh/cwbvh_build.h"
#include "core/error.h"
#include "core/flush_denormals.h"
#include "scenes/scene.h"
#include "simt/gpu_model.h"
#include "simt/simt.h"
#include "simt/simt_cwbvh.h"
#include "simt/timed_replay.h"
#include "tracers/tracer.h"

namespace raycoh {

namespace {
constexpr uint64_t kAlign = 2ull << 20;
uint64_t align_up(uint64_t x) { return (x + kAlign - 1) / kAlign * kAlign; }
}  // namespace

namespace {
SimtConfig simt_config_for(uint64_t node_bytes, uint64_t tri_count, uint32_t warp_size, uint32_t line_bytes,
                           uint32_t sector_bytes) {
  auto pow2_in = [](uint32_t x, uint32_t lo, uint32_t hi) { return x >= lo && x <= hi && (x & (x - 1)) == 0; };
  if (warp_size < 1 || warp_size > kMaxWarpSize)
    throw Error(fmt::format("simt: warp size {} is not in [1, {}]", warp_size, kMaxWarpSize));
  if (!pow2_in(line_bytes, 32, 4096))
    throw Error(fmt::format("simt: line size {} B is not a power of two in [32, 4096]", line_bytes));
  if (!pow2_in(sector_bytes, 16, 4096))
    throw Error(fmt::format("simt: sector size {} B is not a power of two in [16, 4096]", sector_bytes));
  SimtConfig c;
  c.warp_size = warp_size;
  c.line_bytes = line_bytes;
  c.sector_bytes = sector_bytes;
  c.node_base = 0;
  c.tri_base = align_up(node_bytes);
  const uint64_t end = c.tri_base + tri_count * sizeof(BvhTriangle);
  if (end / sector_bytes > 0xFFFFFFFFull)
    throw Error(fmt::format("simt: the BVH's {} bytes exceed the cache model's 32-bit sector numbers", end));
  return c;
}
}  // namespace

SimtConfig simt_config(const BvhView& bvh, uint32_t warp_size, uint32_t line_bytes, uint32_t sector_bytes) {
  return simt_config_for(uint64_t{bvh.node_count} * sizeof(BvhNode), bvh.tri_count, warp_size, line_bytes,
                         sector_bytes);
}
SimtConfig simt_config(const CwbvhView& bvh, uint32_t warp_size, uint32_t line_bytes, uint32_t sector_bytes) {
  return simt_config_for(uint64_t{bvh.node_count} * sizeof(CwbvhNode), bvh.tri_count, warp_size, line_bytes,
                         sector_bytes);
}

namespace {

// Warps traced per chunk: enough work for every thread, and a bounded amount of trace memory in flight
// (a warp of incoherent rays on a large scene keeps tens of KiB of requests).
constexpr size_t kWarpsPerChunk = 1024;

class SimtTracer final : public Tracer {
 public:
  // `cwbvh`: trace that layout instead of `bvh` (null: the BVH2).
  SimtTracer(const Bvh& bvh, std::unique_ptr<Cwbvh> cwbvh, const SimtConfig& simt, const GpuModelConfig& gpu,
             std::string params, const AlphaMasks& alpha)
      : bvh_(bvh.view()),
        cwbvh_(std::move(cwbvh)),
        simt_(simt),
        gpu_(gpu),
        params_(std::move(params)),
        masked_(!alpha.empty()),
        alpha_{alpha.view()} {
    validate(gpu_);
  }

  void trace(const Ray* rays, size_t count, Hit* hits) override {
    CoherenceCounters total;
    total.warp_size = simt_.warp_size;
    total.line_bytes = simt_.line_bytes;
    total.sector_bytes = simt_.sector_bytes;
    const size_t warps = (count + simt_.warp_size - 1) / simt_.warp_size;
    std::vector<WarpTrace> traces(warps);
    std::vector<CoherenceCounters> per_warp(std::min(warps, kWarpsPerChunk));
    // The batch's rays sit after the triangles in the modelled memory, 2 MiB aligned like a cudaMalloc.
    const uint64_t tri_end = simt_.tri_base + uint64_t{bvh_.tri_count} * sizeof(BvhTriangle);  // same triangles
    const uint64_t ray_base = align_up(tri_end);
    if ((ray_base + uint64_t{count} * sizeof(Ray)) / gpu_.cache.sector_bytes > 0xFFFFFFFFull)
      throw Error(fmt::format("simt: {} rays after a BVH of {} bytes exceed the cache model's 32-bit sector numbers",
                              count, tri_end));
    TimedReplay replay(gpu_, warps, ray_base / gpu_.cache.sector_bytes);
    size_t ready = 0;
    while (ready < warps) {
      const size_t end = std::min(warps, ready + kWarpsPerChunk);
      tbb::task_group replaying;
      replaying.run([&replay, &traces, ready] { replay.run(traces, ready); });
      tbb::parallel_for(tbb::blocked_range<size_t>(ready, end, 4), [&](const tbb::blocked_range<size_t>& r) {
        const FlushDenormalsScope ftz;  // the `cpu` tracer's floating-point mode, so that hits match bit for bit
        for (size_t w = r.begin(); w != r.end(); ++w) {
          const size_t first = w * simt_.warp_size;
          const auto lanes = static_cast<uint32_t>(std::min<size_t>(simt_.warp_size, count - first));
          per_warp[w - ready] = CoherenceCounters{};
          CoherenceCounters& c = per_warp[w - ready];
          traces[w].l1_banks = gpu_.gpu.l1_banks;
          traces[w].l1_words = gpu_.gpu.l1_words;
          traces[w].node_load_bytes = gpu_.kernel.node.load_bytes;
          traces[w].triangle_load_bytes = gpu_.kernel.triangle.load_bytes;
          if (cwbvh_ && masked_)
            simt_trace_warp_cwbvh(cwbvh_->view(), rays + first, lanes, simt_, hits + first, c, &traces[w], nullptr,
                                  nullptr, alpha_);
          else if (cwbvh_)
            simt_trace_warp_cwbvh(cwbvh_->view(), rays + first, lanes, simt_, hits + first, c, &traces[w]);
          else if (masked_)
            simt_trace_warp(bvh_, rays + first, lanes, simt_, hits + first, c, &traces[w], nullptr, nullptr, alpha_);
          else
            simt_trace_warp(bvh_, rays + first, lanes, simt_, hits + first, c, &traces[w]);
        }
      });
      replaying.wait();
      for (size_t w = ready; w < end; ++w) total.add(per_warp[w - ready]);
      ready = end;
    }
    replay.run(traces, warps);
    RAYCOH_CHECK(replay.done(), "the timing model stopped before the last warp");
    const MemoryCounters& m = replay.counters();
    total.l1_hits = m.l1_hits;
    total.l1_misses = m.l1_misses;
    total.l2_hits = m.l2_hits;
    total.l2_misses = m.l2_misses;
    total.dram_bytes = m.l2_misses * gpu_.cache.sector_bytes;
    total.modeled = replay.result();
    RAYCOH_CHECK(total.l1_hits + total.l1_misses == total.node_fetches + total.triangle_fetches,
                 fmt::format("{} L1 accesses for {} requested sectors", total.l1_hits + total.l1_misses,
                             total.node_fetches + total.triangle_fetches));
    counters_ = total;
    if (std::getenv("RAYCOH_SIMT_DEBUG")) {
      const ModeledKernel& k = total.modeled;
      std::fprintf(stderr,
                   "simt: %zu rays %.3f ms %.1f MRay/s res %u | busy issue %.0f l1 %.0f l2 %.0f dram %.0f of %.0f "
                   "cycles, tail %.0f | steps n/l/t per warp %.1f %.1f %.1f | L1 miss %.2f L2 miss %.2f /ray\n",
                   count, k.ms, total.modeled_mray_s(), k.resident_warps, k.issue_busy, k.l1_busy, k.l2_busy,
                   k.dram_busy, k.cycles, k.tail_cycles, double(total.node_steps) / total.warps,
                   double(total.leaf_steps) / total.warps, double(total.triangle_steps) / total.warps,
                   total.l1_misses_per_ray(), total.l2_misses_per_ray());
    }
  }

  std::string params() const override { return params_; }
  std::string bvh_layout() const override { return cwbvh_ ? "cwbvh" : "bvh2"; }
  const CoherenceCounters* last_counters() const override { return &counters_; }
  const GpuModelConfig* gpu_model() const override { return &gpu_; }

 private:
  BvhView bvh_;
  std::unique_ptr<Cwbvh> cwbvh_;
  SimtConfig simt_;
  GpuModelConfig gpu_;
  std::string params_;
  bool masked_;      // the scene has alpha cut-outs
  AlphaTest alpha_;  // their any-hit test
  CoherenceCounters counters_;
};

}  // namespace

const ParamTable& simt_params() {
  auto preset_row = [](const char* name, ParamType type, double lo, double hi, const char* doc) {
    return ParamSpec{name, type, "preset", lo, hi, {}, doc};
  };
  static const ParamTable table = {
      choice_param("preset", "rtx3060", gpu_preset_names(), "the modelled GPU (simt/gpu_presets.cpp)"),
      choice_param("kernel", "persistent", {"persistent", "simple"}, "the `cuda` tracer's kernel: warp placement"),
      int_param("block", 128, 32, 1024, "threads per block, a multiple of 32, as the `cuda` tracer's"),
      int_param("warp", 32, 1, 64, "lanes per warp"),
      choice_param("line", "64", {"64", "128"}, "bytes per line of the counted transactions"),
      preset_row("regs", ParamType::Int, 16, 255, "registers per thread of the modelled kernel (occupancy)"),
      int_param("resident", 0, 0, 64, "resident warps per SM; 0 = the kernel's occupancy"),
      preset_row("sms", ParamType::Int, 1, 1024, "streaming multiprocessors"),
      preset_row("l1_kb", ParamType::Int, 1, 65536, "L1 per SM in KiB (4 sets)"),
      preset_row("l2_mb", ParamType::Float, 0.002, 4096, "L2 in MiB (16 ways, whole sets)"),
      preset_row("l1_tags", ParamType::Int, 1, 32, "distinct lines the L1 tag stage resolves per cycle (wavefront)"),
      preset_row("l1_banks", ParamType::Int, 0, 32,
                 "0: l1_tags lines a cycle; N: GPGPU-Sim's rule, a load's distinct sectors N a cycle until a bank "
                 "repeats"),
      preset_row("l1_words", ParamType::Int, 0, 1,
                 "1: the H100's measured rule, a load's 4-byte data banks and 4 hashed tag banks (bench/l1_probe.cu)"),
      preset_row("dram_gbs", ParamType::Float, 1, 100000, "DRAM bandwidth in GB/s"),
      preset_row("l2_bpc", ParamType::Float, 1, 1e6, "L2 bandwidth in bytes per cycle"),
      choice_param("bvh", "bvh2", {"bvh2", "cwbvh"},
                   "layout: the shared BVH2, or the compressed 8-wide BVH (Ylitie et al. 2017) and its kernel's step "
                   "costs"),
      choice_param("traversal", "tuned", {"tuned", "classic"},
                   "the `cuda` BVH2 kernel modelled: tuned (16-byte loads, state in registers) or classic (a 4-byte "
                   "load per field, state in local memory); bvh2 only"),
      preset_row("node_cycles", ParamType::Float, 1, 100000,
                 "partition issue cycles of a node step; default: the kernel's counted cost (98 tuned, 115 classic, "
                 "542 cwbvh)"),
  };
  return table;
}

namespace {

// A row whose default is the preset's value: its range from the table.
const ParamSpec& simt_row(const std::string& name) {
  for (const ParamSpec& s : simt_params())
    if (s.name == name) return s;
  invariant_failed("a simt_params() row", __FILE__, __LINE__, name);
}
int preset_int(ParamSet& p, const std::string& key, uint64_t preset_value) {
  const ParamSpec& s = simt_row(key);
  return p.get_int(key, static_cast<int>(preset_value), static_cast<int>(s.lo), static_cast<int>(s.hi));
}
float preset_float(ParamSet& p, const std::string& key, double preset_value) {
  const ParamSpec& s = simt_row(key);
  return p.get_float(key, static_cast<float>(preset_value), static_cast<float>(s.lo), static_cast<float>(s.hi));
}

}  // namespace

namespace {

// Every parameter of a simt spec read into the modelled GPU (finished: unknown keys throw), before any scene.
struct SimtSettings {
  GpuModelConfig gpu;
  int warp = 32, line = 64;
  bool cwbvh = false;
};

SimtSettings read_simt_settings(ParamSet& params) {
  SimtSettings out;
  GpuModelConfig& gpu = out.gpu;
  gpu = gpu_preset(params.get_choice("preset"));
  KernelSpec& kernel = gpu.kernel;
  kernel.kind = params.get_choice("kernel") == "persistent" ? TraceKernel::Persistent : TraceKernel::Simple;
  kernel.block_threads = static_cast<uint32_t>(params.get_int("block"));
  out.warp = params.get_int("warp");
  out.line = std::stoi(params.get_choice("line"));
  out.cwbvh = params.get_choice("bvh") == "cwbvh";
  const bool classic = params.get_choice("traversal") == "classic";
  if (out.cwbvh && classic)
    throw Error(fmt::format("{}: traversal=classic is a BVH2 kernel; bvh=cwbvh has one kernel (traversal=tuned)",
                            params.owner()));
  // Before the rows whose defaults it sets (regs, node_cycles).
  use_kernel(gpu, out.cwbvh ? TraceKernelChoice::Cwbvh
                  : classic ? TraceKernelChoice::Bvh2Classic
                            : TraceKernelChoice::Bvh2Tuned);
  kernel.regs_per_thread = static_cast<uint32_t>(preset_int(params, "regs", kernel.regs_per_thread));
  gpu.resident_override = static_cast<uint32_t>(params.get_int("resident"));
  CacheModelConfig& cache = gpu.cache;
  cache.sms = static_cast<uint32_t>(preset_int(params, "sms", cache.sms));
  const int l1_kb = preset_int(params, "l1_kb", cache.l1.bytes >> 10);
  const float l2_mb = preset_float(params, "l2_mb", double(cache.l2.bytes) / double(1 << 20));
  gpu.gpu.l1_tags_per_clk = preset_int(params, "l1_tags", static_cast<uint64_t>(gpu.gpu.l1_tags_per_clk));
  gpu.gpu.l1_banks = static_cast<uint32_t>(preset_int(params, "l1_banks", gpu.gpu.l1_banks));
  gpu.gpu.l1_words = preset_int(params, "l1_words", gpu.gpu.l1_words) != 0;
  gpu.gpu.dram_gb_s = preset_float(params, "dram_gbs", gpu.gpu.dram_gb_s);
  gpu.gpu.l2_bytes_per_clk = preset_float(params, "l2_bpc", gpu.gpu.l2_bytes_per_clk);
  kernel.node.issue_cycles = preset_float(params, "node_cycles", kernel.node.issue_cycles);
  params.finish();

  if (kernel.block_threads % 32 != 0)
    throw Error(fmt::format("{}: block={} is not a multiple of 32", params.owner(), kernel.block_threads));
  kernel.warp_size = static_cast<uint32_t>(out.warp);
  cache.l1.bytes = uint64_t(l1_kb) << 10;
  cache.l1.ways = l1_ways_for(cache.l1.bytes, cache.line_bytes);
  const uint64_t l2_set = uint64_t{cache.line_bytes} * cache.l2.ways;
  cache.l2.bytes = static_cast<uint64_t>(std::llround(double(l2_mb) * double(1 << 20))) / l2_set * l2_set;
  if (cache.l2.bytes == 0)
    throw Error(fmt::format("{}: l2_mb={} is smaller than one set ({} bytes)", params.owner(), l2_mb, l2_set));
  return out;
}

}  // namespace

std::unique_ptr<Tracer> make_simt_tracer(ParamSet& params, const Scene& scene, const Bvh& bvh) {
  SimtSettings s = read_simt_settings(params);
  const CacheModelConfig& cache = s.gpu.cache;
  std::unique_ptr<Cwbvh> cwbvh;
  if (s.cwbvh) cwbvh = std::make_unique<Cwbvh>(build_cwbvh(scene, bvh.config));
  const auto warp = static_cast<uint32_t>(s.warp), line = static_cast<uint32_t>(s.line);
  const SimtConfig simt = cwbvh ? simt_config(cwbvh->view(), warp, line, cache.sector_bytes)
                                : simt_config(bvh.view(), warp, line, cache.sector_bytes);
  return std::make_unique<SimtTracer>(bvh, std::move(cwbvh), simt, s.gpu, params.canonical(), scene.alpha);
}

uint64_t simt_resident_rays(const std::string& params) {
  ParamSet set("tracer 'simt'", params, simt_params());
  const SimtSettings s = read_simt_settings(set);
  return uint64_t{s.gpu.cache.sms} * resident_warps(s.gpu) * static_cast<uint64_t>(s.warp);
}

}  // namespace raycoh
