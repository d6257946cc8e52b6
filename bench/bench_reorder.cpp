// raycoh_bench, reordering part: what the encoders' reordering step costs (Meister et al. 2020 measure the same
// overhead against the trace time it saves). Registered at run time, per scene:
//
//   reorder_keys/<scene>/<encoder>               Encoder::encode over the secondary batch; counter Mkeys/s
//   reorder_sort/<sorter>/2M                     2,000,000 (key, index) pairs with uniform random 32-bit keys:
//     sorter  radix8_32bit | radix11_32bit | radix8_64bit | radix11_64bit   radix_sort_pairs, 8/11-bit digits
//             std_stable_sort                std::stable_sort of the same pairs by key
//             speedup                        both on the same input in every iteration; counter
//                                            speedup = std::stable_sort time / radix time (target: >= 4)
//   reorder_step/<scene>/<encoder>/<mode>        reorder(): keys + sort + permute, mode physical | indirect;
//                                                counters key_ms, sort_ms, permute_ms and, for physical, the
//                                                `cpu` trace time of the reordered batch (trace_ms), that of the
//                                                unsorted batch (base_trace_ms), overhead% = reorder / trace_ms
//                                                and e2e = base_trace_ms / (trace_ms + reorder)
//
// Rays: the secondary batch of the harness — primary rays through pixel centres in 8x8 tile order, traced by
// the `cpu` tracer, G-buffer, NoOpt generator (seed 1, frame 0). Scenes: cornell, and sibenik from the shared
// scenes ($RAYCOH_SCENES or the directory fixed at configure time) when it is there. Image size:
// $RAYCOH_BENCH_SIZE=WxH, default 1920x1080 here (the reorder overhead is quoted at that size).
// Times are wall-clock (UseRealTime / manual time): the encoders, the sort and the tracer run on every core.
//
// main() lives in bench_trace.cpp; these benchmarks are registered from a static initialiser in this file, which
// is linked into the executable directly (an object file's initialisers always run, unlike a static library's).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <numeric>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "encoders/encoder.h"
#include "encoders/radix_sort.h"
#include "encoders/reorder.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

constexpr size_t kSortPairs = 2000000;
const std::vector<std::string> kEncoders = {"none", "origin", "reis", "costa", "aila", "twopoint", "mlhcc"};

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

std::pair<int, int> reorder_bench_size() {
  if (const char* env = std::getenv("RAYCOH_BENCH_SIZE")) return parse_size("RAYCOH_BENCH_SIZE", env, 1, 8192);
  return {1920, 1080};
}

struct SecondaryScene {
  Scene scene;
  Bvh bvh;
  RayBatch batch;
  double base_trace_ms = 0.0;  // the unsorted batch, best of 3
};

// The one scene held at a time (benchmarks are registered scene by scene).
std::string cached_spec;
std::unique_ptr<SecondaryScene> cached;

double trace_ms(const Scene& scene, const Bvh& bvh, const std::vector<Ray>& rays) {
  auto tracer = make_tracer(parse_plugin_spec("cpu"), scene, bvh);
  std::vector<Hit> hits(rays.size());
  double best = 1e300;
  for (int i = 0; i < 3; ++i) {
    const auto t = Clock::now();
    tracer->trace(rays.data(), rays.size(), hits.data());
    best = std::min(best, ms_since(t));
  }
  return best;
}

SecondaryScene& secondary_scene(const std::string& spec) {
  if (cached && cached_spec == spec) return *cached;
  cached.reset();
  auto s = std::make_unique<SecondaryScene>();
  s->scene = load_scene(spec);
  s->bvh = build_bvh(s->scene);
  const auto [width, height] = reorder_bench_size();
  const auto order = make_pixel_order(width, height, RayOrder::Tile, 8, 8);
  const FirstHits first =
      first_hits(s->scene, *make_tracer(parse_plugin_spec("cpu"), s->scene, s->bvh), width, height, order, 1, 0, false);
  GenerationStats stats;
  make_generator(parse_plugin_spec("noopt"))->generate(s->scene, first.gbuffer, 1, s->batch, stats);
  s->base_trace_ms = trace_ms(s->scene, s->bvh, s->batch.rays);
  cached = std::move(s);
  cached_spec = spec;
  return *cached;
}

std::unique_ptr<Encoder> encoder_for(const std::string& name, const SecondaryScene& s) {
  return make_encoder(parse_plugin_spec(name), EncoderContext{s.scene.bounds, &s.bvh});
}

void bm_keys(benchmark::State& state, const std::string& scene_spec, const std::string& name) {
  try {
    SecondaryScene& s = secondary_scene(scene_spec);
    auto encoder = encoder_for(name, s);
    std::vector<uint64_t> keys(s.batch.size());
    for (auto _ : state) {
      encoder->encode(s.batch, keys.data());
      benchmark::ClobberMemory();
    }
    const double n = static_cast<double>(s.batch.size());
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(s.batch.size()));
    state.counters["Mkeys/s"] = benchmark::Counter(n * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
    state.counters["rays"] = n;
    std::string label = encoder->params();
    if (!encoder->details().empty()) label.append(" ").append(encoder->details());
    state.SetLabel(label);
  } catch (const Error& e) {
    state.SkipWithError(e.what());
  }
}

struct SortInput {
  std::vector<uint64_t> keys;
  std::vector<std::pair<uint64_t, uint32_t>> pairs;  // the same (key, index) pairs for std::stable_sort
};

const SortInput& sort_input() {
  static const SortInput input = [] {
    SortInput in;
    std::mt19937_64 rng(2024);
    in.keys.resize(kSortPairs);
    in.pairs.resize(kSortPairs);
    for (size_t i = 0; i < kSortPairs; ++i) {
      in.keys[i] = rng() & 0xFFFFFFFFull;
      in.pairs[i] = {in.keys[i], static_cast<uint32_t>(i)};
    }
    return in;
  }();
  return input;
}

// Radix sort of a fresh copy of the input; returns its milliseconds.
double time_radix(const SortInput& in, int bits, int digit_bits, std::vector<uint64_t>& keys,
                  std::vector<uint32_t>& values, RadixSortScratch& scratch) {
  keys = in.keys;
  values.resize(keys.size());
  const auto t = Clock::now();
  std::iota(values.begin(), values.end(), 0u);
  radix_sort_pairs(keys, values, bits, scratch, digit_bits);
  return ms_since(t);
}

double time_std(const SortInput& in, std::vector<std::pair<uint64_t, uint32_t>>& pairs) {
  pairs = in.pairs;
  const auto t = Clock::now();
  std::stable_sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return ms_since(t);
}

void bm_sort_radix(benchmark::State& state, int bits, int digit_bits) {
  const SortInput& in = sort_input();
  std::vector<uint64_t> keys;
  std::vector<uint32_t> values;
  RadixSortScratch scratch;
  scratch.reserve(kSortPairs);
  for (auto _ : state) state.SetIterationTime(time_radix(in, bits, digit_bits, keys, values, scratch) * 1e-3);
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(kSortPairs));
}

void bm_sort_std(benchmark::State& state) {
  const SortInput& in = sort_input();
  std::vector<std::pair<uint64_t, uint32_t>> pairs;
  for (auto _ : state) state.SetIterationTime(time_std(in, pairs) * 1e-3);
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(kSortPairs));
}

void bm_sort_speedup(benchmark::State& state) {
  const SortInput& in = sort_input();
  std::vector<uint64_t> keys;
  std::vector<uint32_t> values;
  std::vector<std::pair<uint64_t, uint32_t>> pairs;
  RadixSortScratch scratch;
  scratch.reserve(kSortPairs);
  double radix_total = 0.0, std_total = 0.0;
  bool same = true;
  for (auto _ : state) {
    const double radix = time_radix(in, 32, kDefaultRadixDigitBits, keys, values, scratch);
    std_total += time_std(in, pairs);
    radix_total += radix;
    state.SetIterationTime(radix * 1e-3);
    for (size_t i = 0; i < kSortPairs && same; i += 997) same = values[i] == pairs[i].second;
  }
  if (!same) state.SkipWithError("radix sort and std::stable_sort disagree");
  const double iterations = static_cast<double>(state.iterations());
  state.counters["radix_ms"] = radix_total / iterations;
  state.counters["std_ms"] = std_total / iterations;
  state.counters["speedup"] = radix_total > 0.0 ? std_total / radix_total : 0.0;
}

void bm_step(benchmark::State& state, const std::string& scene_spec, const std::string& name, PermuteMode mode) {
  try {
    SecondaryScene& s = secondary_scene(scene_spec);
    auto encoder = encoder_for(name, s);
    RayBatch out;
    std::vector<uint32_t> order;
    ReorderTimings t, sum;
    for (auto _ : state) {
      reorder(*encoder, s.batch, mode, out, order, t);
      sum.key_ms += t.key_ms;
      sum.sort_ms += t.sort_ms;
      sum.permute_ms += t.permute_ms;
      state.SetIterationTime(t.total_ms() * 1e-3);
    }
    const double iterations = static_cast<double>(state.iterations());
    const double total = sum.total_ms() / iterations;
    state.counters["key_ms"] = sum.key_ms / iterations;
    state.counters["sort_ms"] = sum.sort_ms / iterations;
    state.counters["permute_ms"] = sum.permute_ms / iterations;
    state.counters["rays"] = static_cast<double>(s.batch.size());
    if (mode == PermuteMode::Physical) {
      // `none` traces the batch as generated; the others trace what reorder() wrote into out.
      const double traced = encoder->key_bits() == 0 ? s.base_trace_ms : trace_ms(s.scene, s.bvh, out.rays);
      state.counters["trace_ms"] = traced;
      state.counters["base_trace_ms"] = s.base_trace_ms;
      state.counters["overhead%"] = traced > 0.0 ? 100.0 * total / traced : 0.0;
      state.counters["e2e"] = s.base_trace_ms / (traced + total);
    }
    state.SetLabel(encoder->params());
  } catch (const Error& e) {
    state.SkipWithError(e.what());
  }
}

std::vector<std::pair<std::string, std::string>> reorder_scenes() {  // (name, spec)
  std::vector<std::pair<std::string, std::string>> scenes = {{"cornell", "cornell"}};
  const std::filesystem::path dir = std::getenv("RAYCOH_SCENES") ? std::getenv("RAYCOH_SCENES") : RAYCOH_SHARED_SCENES;
  const std::filesystem::path sibenik = dir / "sibenik" / "sibenik.glb";
  std::error_code ec;
  if (std::filesystem::exists(sibenik, ec)) scenes.emplace_back("sibenik", sibenik.string());
  return scenes;
}

void register_reorder_benchmarks() {
  for (const auto& [name, spec] : reorder_scenes())
    for (const std::string& encoder : kEncoders)
      if (encoder != "none")
        benchmark::RegisterBenchmark(("reorder_keys/" + name + "/" + encoder).c_str(), bm_keys, spec, encoder)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
  for (int bits : {32, 64})
    for (int digit : {8, 11})
      benchmark::RegisterBenchmark(
          ("reorder_sort/radix" + std::to_string(digit) + "_" + std::to_string(bits) + "bit/2M").c_str(), bm_sort_radix,
          bits, digit)
          ->Unit(benchmark::kMillisecond)
          ->UseManualTime();
  benchmark::RegisterBenchmark("reorder_sort/std_stable_sort/2M", bm_sort_std)
      ->Unit(benchmark::kMillisecond)
      ->UseManualTime();
  benchmark::RegisterBenchmark("reorder_sort/speedup/2M", bm_sort_speedup)
      ->Unit(benchmark::kMillisecond)
      ->UseManualTime();
  for (const auto& [name, spec] : reorder_scenes())
    for (const std::string& encoder : kEncoders)
      for (PermuteMode mode : {PermuteMode::Physical, PermuteMode::Indirect})
        if (encoder != "none" || mode == PermuteMode::Physical) {
          auto* b = benchmark::RegisterBenchmark(
              ("reorder_step/" + name + "/" + encoder + "/" + to_string(mode)).c_str(), bm_step, spec, encoder, mode);
          b->Unit(benchmark::kMillisecond)->UseManualTime();
          if (encoder == "none") b->Iterations(1);  // nothing to time: the row shows the unsorted trace
        }
}

}  // namespace
}  // namespace raycoh

int main(int argc, char** argv) {
  try {
    const auto [width, height] = raycoh::reorder_bench_size();
    benchmark::AddCustomContext("reorder image", std::to_string(width) + "x" + std::to_string(height) +
                                                     ", secondary rays of noopt, 8x8 tile order");
    raycoh::register_reorder_benchmarks();
  } catch (const raycoh::Error& e) {
    std::fprintf(stderr, "raycoh_bench_reorder: error: %s\n", e.what());
    return 2;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
