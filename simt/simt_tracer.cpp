// Tracer `simt`: a CPU model of a GPU running our traversal. Warps of consecutive rays of the batch run the
// while-while traversal in lock step (simt/simt.h: the exact stepping and counting rules), and every warp
// step's fetches go through a cache model of per-SM L1s and a shared L2 (simt/cache_model.h). Its hits equal the
// `cpu` tracer's bit for bit; its product is the CoherenceCounters of last_counters(), not its wall-clock time.
//
// Parameters
//   preset    string  rtx3060   rtx3060 | h100: SM count, cache sizes and cost weights (simt/cache_model.h)
//   warp      int     32        [1, 64]: lanes per warp
//   line      int     64        64 | 128: bytes per line of the node/triangle transactions
//   sms       int     preset    [1, 1024]: SMs
//   l1_kb     int     preset    [1, 65536]: L1 per SM, KiB (4 sets, ways = l1_kb * 2)
//   l2_mb     float   preset    [0.002, 4096]: shared L2, MiB (16 ways; rounded down to whole sets)
//   resident  int     32        [1, 64]: warps resident per SM (the schedule's slots)
//   block     int     2         [1, 32]: consecutive warps per thread block, kept on one SM (warp w runs on SM
//                               (w / block) % sms; 2 = one 64-thread block per 8x8 tile)
//
// Determinism and speed: the counters depend on the batch and its order only, never on the thread count. Warps are
// traced in parallel with oneTBB, a chunk at a time, each producing its trace of cache requests; the cache model
// replays the traces in its fixed global order on one thread, overlapped with tracing the next chunk. Sources: Aila &
// Laine, HPG 2009 (while-while traversal, speculative node walk); the presets' sources are listed in simt/cache_model.h.
#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <cmath>
#include <memory>

#include "core/error.h"
#include "bvh/bvh_build.h"
#include "simt/cache_model.h"
#include "core/flush_denormals.h"
#include "simt/simt.h"
#include "tracers/tracer.h"

namespace raycoh {

SimtConfig simt_config(const BvhView& bvh, uint32_t warp_size, uint32_t line_bytes, uint32_t sector_bytes) {
  auto pow2_in = [](uint32_t x, uint32_t lo, uint32_t hi) { return x >= lo && x <= hi && (x & (x - 1)) == 0; };
  if (warp_size < 1 || warp_size > kMaxWarpSize)
    throw Error(fmt::format("simt: warp size {} is not in [1, {}]", warp_size, kMaxWarpSize));
  if (!pow2_in(line_bytes, 32, 4096))
    throw Error(fmt::format("simt: line size {} B is not a power of two in [32, 4096]", line_bytes));
  if (!pow2_in(sector_bytes, 16, 4096))
    throw Error(fmt::format("simt: sector size {} B is not a power of two in [16, 4096]", sector_bytes));
  constexpr uint64_t kAlign = 2ull << 20;
  SimtConfig c;
  c.warp_size = warp_size;
  c.line_bytes = line_bytes;
  c.sector_bytes = sector_bytes;
  c.node_base = 0;
  c.tri_base = (uint64_t{bvh.node_count} * sizeof(BvhNode) + kAlign - 1) / kAlign * kAlign;
  const uint64_t end = c.tri_base + uint64_t{bvh.tri_count} * sizeof(BvhTriangle);
  if (end / sector_bytes > 0xFFFFFFFFull)
    throw Error(fmt::format("simt: the BVH's {} bytes exceed the cache model's 32-bit sector numbers", end));
  return c;
}

namespace {

// Warps traced per chunk: enough work for every thread, and a bounded amount of trace memory in flight
// (a warp of incoherent rays on a large scene keeps tens of KiB of requests).
constexpr size_t kWarpsPerChunk = 1024;

class SimtTracer final : public Tracer {
 public:
  SimtTracer(const Bvh& bvh, const SimtConfig& simt, const CacheModelConfig& cache, std::string params)
      : bvh_(bvh.view()), simt_(simt), cache_(cache), params_(std::move(params)) {
    validate(cache_);
  }

  void trace(const Ray* rays, size_t count, Hit* hits) override {
    CoherenceCounters total;
    total.warp_size = simt_.warp_size;
    total.line_bytes = simt_.line_bytes;
    total.sector_bytes = simt_.sector_bytes;
    const size_t warps = (count + simt_.warp_size - 1) / simt_.warp_size;
    std::vector<WarpTrace> traces(warps);
    std::vector<CoherenceCounters> per_warp(std::min(warps, kWarpsPerChunk));
    WarpScheduleReplay replay(cache_, warps);
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
          simt_trace_warp(bvh_, rays + first, lanes, simt_, hits + first, per_warp[w - ready], &traces[w]);
        }
      });
      replaying.wait();
      for (size_t w = ready; w < end; ++w) add_warp_counters(total, per_warp[w - ready]);
      ready = end;
    }
    replay.run(traces, warps);
    RAYCOH_CHECK(replay.done(), "the cache replay stopped before the last warp");
    const MemoryCounters& m = replay.counters();
    total.l1_hits = m.l1_hits;
    total.l1_misses = m.l1_misses;
    total.l2_hits = m.l2_hits;
    total.l2_misses = m.l2_misses;
    total.dram_bytes = m.l2_misses * cache_.sector_bytes;
    total.modeled_cost = modeled_cost(total, cache_.cost);
    RAYCOH_CHECK(total.l1_hits + total.l1_misses == total.node_fetches + total.triangle_fetches,
                 fmt::format("{} L1 accesses for {} requested sectors", total.l1_hits + total.l1_misses,
                             total.node_fetches + total.triangle_fetches));
    counters_ = total;
  }

  std::string params() const override { return params_; }
  const CoherenceCounters* last_counters() const override { return &counters_; }

 private:
  BvhView bvh_;
  SimtConfig simt_;
  CacheModelConfig cache_;
  std::string params_;
  CoherenceCounters counters_;
};

}  // namespace

std::unique_ptr<Tracer> make_simt_tracer(ParamSet& params, const Scene&, const Bvh& bvh) {
  const std::string preset = params.get_choice("preset", "rtx3060", cache_preset_names());
  CacheModelConfig cache = cache_preset(preset);
  const int warp = params.get_int("warp", 32, 1, static_cast<int>(kMaxWarpSize));
  const int line = std::stoi(params.get_choice("line", "64", {"64", "128"}));
  cache.sms = static_cast<uint32_t>(params.get_int("sms", static_cast<int>(cache.sms), 1, 1024));
  const int l1_kb = params.get_int("l1_kb", static_cast<int>(cache.l1.bytes >> 10), 1, 65536);
  const float l2_mb = params.get_float("l2_mb", static_cast<float>(cache.l2.bytes) / float(1 << 20), 0.002f, 4096.f);
  cache.resident_warps =
      static_cast<uint32_t>(params.get_int("resident", static_cast<int>(cache.resident_warps), 1, 64));
  cache.block_warps = static_cast<uint32_t>(params.get_int("block", static_cast<int>(cache.block_warps), 1, 32));
  params.finish();

  cache.l1.bytes = uint64_t(l1_kb) << 10;
  cache.l1.ways = l1_ways_for(cache.l1.bytes, cache.line_bytes);
  const uint64_t l2_set = uint64_t{cache.line_bytes} * cache.l2.ways;
  cache.l2.bytes = static_cast<uint64_t>(std::llround(double(l2_mb) * double(1 << 20))) / l2_set * l2_set;
  if (cache.l2.bytes == 0)
    throw Error(fmt::format("{}: l2_mb={} is smaller than one set ({} bytes)", params.owner(), l2_mb, l2_set));
  const SimtConfig simt =
      simt_config(bvh.view(), static_cast<uint32_t>(warp), static_cast<uint32_t>(line), cache.sector_bytes);
  return std::make_unique<SimtTracer>(bvh, simt, cache, params.canonical());
}

}  // namespace raycoh
