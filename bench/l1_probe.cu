// raycoh_bench_l1: how many cycles the L1 needs for one warp-wide global load, as a function of the lines, sectors
// and sector positions its lanes touch (bench/l1_patterns.h). The simt model's hardware presets charge
// max(1, ceil(lines / 4)) a load; on an H100 the BVH2 trace kernel needed 1.55-1.63x the modeled wavefronts
// (results/gpu/h100-9bc790a-ncu/README.md). This probe measures the rule instead of fitting it.
//
// Each pattern runs a kernel whose warps all repeat the same 8 independent loads (one per 4 KB page, so 32 KB in
// all, L1-resident after a warm-up pass; the L1 gets the largest carve-out) and add the values up. Per SM, the
// cycles from the first block's start to the last block's end (clock64, SM-local) over the warp load instructions
// it executed give cycles per load: the L1 data stage's wavefronts per request when that stage is the bottleneck.
// Run it under Nsight Compute (--ncu: one short launch per pattern) for the wavefront counts themselves:
//   raycoh_bench_l1 --out l1.csv
//   ncu --metrics l1tex__data_pipe_lsu_wavefronts_mem_global_op_ld.sum,... raycoh_bench_l1 --ncu --out l1-ncu.csv
// Options: --iters N (loop trips, default 512), --blocks-per-sm N (4), --threads N (256), --random N (node-like
// random patterns, 48), --seed S (1), --width W (only patterns of that width), --span N (N patterns over a 64 KB
// span, bank-free, for the tag stage's hash; --span-only: those alone), --out FILE (CSV; default stdout).
#include <cuda_runtime.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "bench/probe_provenance.h"
#include "l1_patterns.h"

namespace {

using raycoh::l1probe::kPage;
using raycoh::l1probe::Pattern;

#define PROBE_CHECK(call)                                                               \
  do {                                                                                  \
    const cudaError_t e_ = (call);                                                      \
    if (e_ != cudaSuccess) {                                                            \
      std::fprintf(stderr, "raycoh_bench_l1: %s: %s\n", #call, cudaGetErrorString(e_)); \
      std::exit(1);                                                                     \
    }                                                                                   \
  } while (0)

constexpr int kLoads = 8;  // independent loads per trip, one per page

// volatile with a memory clobber: every load is issued as written (not hoisted out of the loop or merged).
template <int W>
__device__ __forceinline__ unsigned load(const unsigned char* p) {
  unsigned a, b, c, d;
  if constexpr (W == 4) {
    asm volatile("ld.global.nc.u32 %0, [%1];" : "=r"(a) : "l"(p) : "memory");
    return a;
  } else if constexpr (W == 8) {
    asm volatile("ld.global.nc.v2.u32 {%0, %1}, [%2];" : "=r"(a), "=r"(b) : "l"(p) : "memory");
    return a + b;
  } else {
    asm volatile("ld.global.nc.v4.u32 {%0, %1, %2, %3}, [%4];"
                 : "=r"(a), "=r"(b), "=r"(c), "=r"(d)
                 : "l"(p)
                 : "memory");
    return a + b + c + d;
  }
}

template <int W>
__device__ __forceinline__ unsigned trip(const unsigned char* p, unsigned stride) {
  unsigned acc = 0;
#pragma unroll
  for (int j = 0; j < kLoads; ++j) acc += load<W>(p + j * stride);
  return acc;
}

// GPGPU-Sim (RAYCOH_CUDA_SIM builds) implements neither %clock64 nor %smid: there the 32-bit clock (a run of
// milliseconds cannot wrap it) and SM 0 (run the simulator with one SM).
__device__ __forceinline__ long long sm_clock() {
#ifdef RAYCOH_CUDA_SIM
  unsigned c;
  asm volatile("mov.u32 %0, %%clock;" : "=r"(c));
  return c;
#else
  return clock64();
#endif
}

__device__ __forceinline__ unsigned sm_id() {
  unsigned smid = 0;
#ifndef RAYCOH_CUDA_SIM
  asm volatile("mov.u32 %0, %%smid;" : "=r"(smid));
#endif
  return smid;
}

template <int W>
__global__ void probe_kernel(const unsigned char* __restrict__ pages, const unsigned* __restrict__ offsets, int iters,
                             unsigned stride, unsigned zero, unsigned* __restrict__ sink,
                             long long* __restrict__ clocks) {
  const unsigned char* p = pages + offsets[threadIdx.x & 31];
  unsigned acc = trip<W>(p, stride);  // warm-up: the footprint (32 or 64 KB) into L1
  __syncthreads();
  const long long t0 = sm_clock();
  // `zero` is 0 at run time; the compiler cannot know it, so each trip's loads stay in the loop (ptxas hoists a
  // read-only load whose address does not change, volatile or not).
  for (int i = 0; i < iters; ++i) acc += trip<W>(p + i * zero, stride);
  __syncthreads();
  const long long t1 = sm_clock();
  sink[blockIdx.x * blockDim.x + threadIdx.x] = acc;
  if (threadIdx.x == 0) {
    clocks[3 * blockIdx.x] = t0;
    clocks[3 * blockIdx.x + 1] = t1;
    clocks[3 * blockIdx.x + 2] = sm_id();
  }
}

struct Options {
  int iters = 512, blocks_per_sm = 4, threads = 256, random = 48, width = 0, span = 0;
  bool span_only = false;
  unsigned seed = 1;
  bool ncu = false;
  std::string out;
};

[[noreturn]] void usage(const char* why) {
  std::fprintf(stderr,
               "raycoh_bench_l1: %s (options: --iters N --blocks-per-sm N --threads N --random N --seed S "
               "--width 4|8|16 --span N --span-only --ncu --out FILE)\n",
               why);
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> long {
      if (i + 1 >= argc) usage(("option " + a + " needs a value").c_str());
      char* end = nullptr;
      const long v = std::strtol(argv[++i], &end, 10);
      if (*end != '\0' || v < 0 || v > 1 << 20) usage(("option " + a + ": not a count in [0, 1048576]").c_str());
      return v;
    };
    if (a == "--iters")
      o.iters = static_cast<int>(value());
    else if (a == "--blocks-per-sm")
      o.blocks_per_sm = static_cast<int>(value());
    else if (a == "--threads")
      o.threads = static_cast<int>(value());
    else if (a == "--random")
      o.random = static_cast<int>(value());
    else if (a == "--seed")
      o.seed = static_cast<unsigned>(value());
    else if (a == "--width")
      o.width = static_cast<int>(value());
    else if (a == "--span")
      o.span = static_cast<int>(value());
    else if (a == "--span-only")
      o.span_only = true;
    else if (a == "--ncu")
      o.ncu = true;
    else if (a == "--out") {
      if (++i >= argc) usage("--out needs a file");
      o.out = argv[i];
    } else
      usage(("unknown option '" + a + "'").c_str());
  }
  if (o.iters < 1 || o.threads < 32 || o.threads > 1024 || o.threads % 32 || o.blocks_per_sm < 1)
    usage("--iters >= 1, --threads a multiple of 32 in [32, 1024], --blocks-per-sm >= 1");
  if (o.width != 0 && o.width != 4 && o.width != 8 && o.width != 16) usage("--width is 4, 8 or 16");
  if (o.ncu) o.iters = std::min(o.iters, 64), o.blocks_per_sm = 1;  // counts, not time: short launches
  return o;
}

struct Measured {
  double cycles_per_load = 0, min_sm = 0, max_sm = 0, kernel_ms = 0;
};

void launch(int width, int grid, int threads, const unsigned char* pages, const unsigned* offsets, int iters,
            unsigned stride, unsigned* sink, long long* clocks) {
  if (width == 4)
    probe_kernel<4><<<grid, threads>>>(pages, offsets, iters, stride, 0, sink, clocks);
  else if (width == 8)
    probe_kernel<8><<<grid, threads>>>(pages, offsets, iters, stride, 0, sink, clocks);
  else
    probe_kernel<16><<<grid, threads>>>(pages, offsets, iters, stride, 0, sink, clocks);
  PROBE_CHECK(cudaGetLastError());
}

// Per SM: (last end - first start) / warp load instructions of its blocks; the median over SMs, and the spread.
Measured per_sm(const std::vector<long long>& clocks, int grid, int sms, double loads_per_block) {
  std::vector<long long> first(sms, 0), last(sms, 0);
  std::vector<int> blocks(sms, 0);
  for (int b = 0; b < grid; ++b) {
    const long long t0 = clocks[3 * b], t1 = clocks[3 * b + 1];
    const int sm = static_cast<int>(clocks[3 * b + 2]);
    if (sm < 0 || sm >= sms) continue;
    first[sm] = blocks[sm] ? std::min(first[sm], t0) : t0;
    last[sm] = blocks[sm] ? std::max(last[sm], t1) : t1;
    ++blocks[sm];
  }
  std::vector<double> per;
  for (int sm = 0; sm < sms; ++sm)
    if (blocks[sm]) per.push_back(static_cast<double>(last[sm] - first[sm]) / (blocks[sm] * loads_per_block));
  std::sort(per.begin(), per.end());
  Measured m;
  if (per.empty()) return m;
  m.cycles_per_load = per[per.size() / 2];
  m.min_sm = per.front();
  m.max_sm = per.back();
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  raycoh::probe_provenance_start(argc, argv);
  cudaDeviceProp prop{};
  PROBE_CHECK(cudaGetDeviceProperties(&prop, 0));
  for (auto k : {probe_kernel<4>, probe_kernel<8>, probe_kernel<16>})  // all of the unified memory as L1
    PROBE_CHECK(cudaFuncSetAttribute(k, cudaFuncAttributePreferredSharedMemoryCarveout, 0));
  const int sms = prop.multiProcessorCount, grid = sms * o.blocks_per_sm;
  unsigned char* pages = nullptr;
  unsigned *offsets = nullptr, *sink = nullptr;
  long long* clocks = nullptr;
  const size_t footprint = std::max<size_t>(kLoads * kPage, raycoh::l1probe::kSpan);
  PROBE_CHECK(cudaMalloc(&pages, footprint));
  std::vector<unsigned char> host_pages(footprint);
  for (size_t i = 0; i < host_pages.size(); ++i) host_pages[i] = static_cast<unsigned char>(i * 131 + 7);
  PROBE_CHECK(cudaMemcpy(pages, host_pages.data(), host_pages.size(), cudaMemcpyHostToDevice));
  PROBE_CHECK(cudaMalloc(&offsets, 32 * sizeof(unsigned)));
  PROBE_CHECK(cudaMalloc(&sink, static_cast<size_t>(grid) * o.threads * sizeof(unsigned)));
  PROBE_CHECK(cudaMalloc(&clocks, static_cast<size_t>(grid) * 3 * sizeof(long long)));
  cudaEvent_t start, stop;
  PROBE_CHECK(cudaEventCreate(&start));
  PROBE_CHECK(cudaEventCreate(&stop));

  FILE* out = o.out.empty() ? stdout : std::fopen(o.out.c_str(), "w");
  if (!out) usage(("cannot write " + o.out).c_str());
  std::fprintf(out, "# raycoh_bench_l1 on %s (%d SMs, sm_%d%d), %s, iters %d, %d blocks of %d threads\n", prop.name,
               sms, prop.major, prop.minor, o.ncu ? "ncu mode (one launch per pattern)" : "timed", o.iters, grid,
               o.threads);
  std::fprintf(out,
               "launch,pattern,width,lines,sectors,bank_max,gpgpusim,lines4,sectors4,bytes128,"
               "cycles_per_load,min_sm,max_sm,kernel_ms,offsets%s\n",
               raycoh::probe_provenance_header().c_str());
  int index = 0;
  std::vector<Pattern> patterns;
  if (!o.span_only) patterns = raycoh::l1probe::all_patterns(o.random, o.seed);
  const size_t regular = patterns.size();
  for (const Pattern& p : raycoh::l1probe::span_patterns(o.span, o.seed)) patterns.push_back(p);
  for (size_t i = 0; i < patterns.size(); ++i) {
    const Pattern& p = patterns[i];
    if (o.width && static_cast<int>(p.width) != o.width) continue;
    const unsigned stride = i < regular ? kPage : 0;  // span patterns: the 8 loads at the same addresses
    PROBE_CHECK(cudaMemcpy(offsets, p.offsets.data(), sizeof(p.offsets), cudaMemcpyHostToDevice));
    if (!o.ncu) launch(p.width, grid, o.threads, pages, offsets, o.iters, stride, sink, clocks);  // warm-up launch
    PROBE_CHECK(cudaEventRecord(start));
    launch(p.width, grid, o.threads, pages, offsets, o.iters, stride, sink, clocks);
    PROBE_CHECK(cudaEventRecord(stop));
    PROBE_CHECK(cudaEventSynchronize(stop));
    std::vector<long long> host_clocks(static_cast<size_t>(grid) * 3);
    PROBE_CHECK(cudaMemcpy(host_clocks.data(), clocks, host_clocks.size() * sizeof(long long), cudaMemcpyDeviceToHost));
    Measured m = per_sm(host_clocks, grid, sms, static_cast<double>(o.threads / 32) * o.iters * kLoads);
    float ms = 0;
    PROBE_CHECK(cudaEventElapsedTime(&ms, start, stop));
    m.kernel_ms = ms;
    const auto f = raycoh::l1probe::features(p);
    std::fprintf(out, "%d,%s,%u,%u,%u,%u,%u,%u,%u,%u,%.4f,%.4f,%.4f,%.4f,", index++, p.name.c_str(), p.width, f.lines,
                 f.sectors, f.bank_max, f.gpgpusim, f.lines4, f.sectors4, f.bytes128, m.cycles_per_load, m.min_sm,
                 m.max_sm, m.kernel_ms);
    for (size_t i = 0; i < p.offsets.size(); ++i) std::fprintf(out, "%s%u", i ? " " : "", p.offsets[i]);
    std::fprintf(out, "%s\n", raycoh::probe_provenance_values().c_str());
  }
  if (out != stdout) std::fclose(out);
  PROBE_CHECK(cudaFree(pages));
  PROBE_CHECK(cudaFree(offsets));
  PROBE_CHECK(cudaFree(sink));
  PROBE_CHECK(cudaFree(clocks));
  return 0;
}
