// raycoh_bench_stages: what a GPU allows the device pipeline's stages, measured on that GPU, to set each measured
// stage beside (scripts/gpu-check's stage table):
//   copy      a streaming copy kernel (16-byte loads and stores) over 2 x 512 MB: the bandwidth a stage that reads
//             and writes its bytes once can reach; a stage's traffic bound is its bytes over this bandwidth.
//   memcpy    cudaMemcpy device to device of the same buffers, for comparison.
//   launch    back-to-back launches of an empty kernel on one stream: the gap a stage pays per kernel.
//   sort      CUB's DeviceRadixSort::SortPairs of n (key, index) pairs over bits [0, bits), keys as 32-bit words for
//             bits <= 32 (as cuda/device_keys.cu sorts them), uniform random keys, buffers allocated once: CUB's
//             own time, to set the pipeline's sort stage beside.
// Every figure is the median of --repeat timed runs after one warm-up (CUDA events), with the fastest beside it.
// Options: --n N (pairs to sort, default 2073600 = 1920x1080), --repeat R (20), --out FILE (CSV; default stdout).
// Output columns: measure,bits,n,bytes,median_ms,min_ms,gb_s (gb_s: bytes / median; empty where not a transfer).
#include <cuda_runtime.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cub/device/device_radix_sort.cuh>
#include <string>
#include <vector>

#include "bench/probe_provenance.h"

namespace {

#define STAGE_CHECK(call)                                                                   \
  do {                                                                                      \
    const cudaError_t e_ = (call);                                                          \
    if (e_ != cudaSuccess) {                                                                \
      std::fprintf(stderr, "raycoh_bench_stages: %s: %s\n", #call, cudaGetErrorString(e_)); \
      std::exit(1);                                                                         \
    }                                                                                       \
  } while (0)

__global__ void copy_kernel(const float4* __restrict__ in, float4* __restrict__ out, size_t n) {
  for (size_t i = blockIdx.x * size_t{blockDim.x} + threadIdx.x; i < n; i += size_t{gridDim.x} * blockDim.x)
    out[i] = in[i];
}

__global__ void empty_kernel() {}

__global__ void random_keys_kernel(uint32_t* k32, uint64_t* k64, uint32_t* index, size_t n, uint64_t bits_mask) {
  const size_t i = blockIdx.x * size_t{blockDim.x} + threadIdx.x;
  if (i >= n) return;
  uint64_t x = (i + 1) * 0x9E3779B97F4A7C15ull;  // splitmix64
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  x ^= x >> 31;
  k64[i] = x & bits_mask;
  k32[i] = static_cast<uint32_t>(x & bits_mask);
  index[i] = static_cast<uint32_t>(i);
}

struct Times {
  double median_ms = 0, min_ms = 0;
};

// Median and fastest of `repeat` runs of f() between two events, after one warm-up run.
template <class F>
Times time_runs(int repeat, F&& f) {
  cudaEvent_t a, b;
  STAGE_CHECK(cudaEventCreate(&a));
  STAGE_CHECK(cudaEventCreate(&b));
  f();
  std::vector<double> ms;
  for (int r = 0; r < repeat; ++r) {
    STAGE_CHECK(cudaEventRecord(a));
    f();
    STAGE_CHECK(cudaEventRecord(b));
    STAGE_CHECK(cudaEventSynchronize(b));
    float t = 0;
    STAGE_CHECK(cudaEventElapsedTime(&t, a, b));
    ms.push_back(t);
  }
  STAGE_CHECK(cudaEventDestroy(a));
  STAGE_CHECK(cudaEventDestroy(b));
  std::sort(ms.begin(), ms.end());
  return Times{ms[ms.size() / 2], ms.front()};
}

void row(FILE* out, const char* measure, int bits, size_t n, double bytes, const Times& t) {
  std::fprintf(out, "%s,%d,%zu,%.0f,%.6f,%.6f,", measure, bits, n, bytes, t.median_ms, t.min_ms);
  const std::string provenance = raycoh::probe_provenance_values();
  if (bytes > 0)
    std::fprintf(out, "%.1f%s\n", bytes / (t.median_ms * 1e6), provenance.c_str());
  else
    std::fprintf(out, "%s\n", provenance.c_str());
}

template <class K>
Times cub_sort(const K* in, K* out, const uint32_t* values, uint32_t* order, size_t n, int bits, int repeat) {
  size_t bytes = 0;
  STAGE_CHECK(cub::DeviceRadixSort::SortPairs(nullptr, bytes, in, out, values, order, static_cast<int>(n), 0, bits));
  void* temp = nullptr;
  STAGE_CHECK(cudaMalloc(&temp, bytes));
  const Times t = time_runs(repeat, [&] {
    STAGE_CHECK(cub::DeviceRadixSort::SortPairs(temp, bytes, in, out, values, order, static_cast<int>(n), 0, bits));
  });
  STAGE_CHECK(cudaFree(temp));
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  size_t n = 1920 * 1080;
  int repeat = 20;
  std::string out_path;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--n" && i + 1 < argc) {
      n = std::strtoull(argv[++i], nullptr, 10);
    } else if (a == "--repeat" && i + 1 < argc) {
      repeat = std::atoi(argv[++i]);
    } else if (a == "--out" && i + 1 < argc) {
      out_path = argv[++i];
    } else {
      std::fprintf(stderr, "raycoh_bench_stages: unknown option '%s' (valid: --n N, --repeat R, --out FILE)\n",
                   a.c_str());
      return 2;
    }
  }
  if (n < 2 || n > 0x7fffffffu || repeat < 1) {
    std::fprintf(stderr, "raycoh_bench_stages: --n must be in [2, 2^31) and --repeat >= 1\n");
    return 2;
  }
  FILE* out = out_path.empty() ? stdout : std::fopen(out_path.c_str(), "w");
  if (!out) {
    std::fprintf(stderr, "raycoh_bench_stages: cannot write %s\n", out_path.c_str());
    return 2;
  }
  raycoh::probe_provenance_start(argc, argv);
  std::fprintf(out, "measure,bits,n,bytes,median_ms,min_ms,gb_s%s\n", raycoh::probe_provenance_header().c_str());

  const size_t copy_bytes = size_t{512} << 20, vecs = copy_bytes / sizeof(float4);
  float4 *src = nullptr, *dst = nullptr;
  STAGE_CHECK(cudaMalloc(&src, copy_bytes));
  STAGE_CHECK(cudaMalloc(&dst, copy_bytes));
  STAGE_CHECK(cudaMemset(src, 1, copy_bytes));
  int sms = 0;
  STAGE_CHECK(cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, 0));
  row(out, "copy", 0, vecs, 2.0 * copy_bytes,
      time_runs(repeat, [&] { copy_kernel<<<sms * 8, 256>>>(src, dst, vecs); }));
  row(out, "memcpy", 0, vecs, 2.0 * copy_bytes,
      time_runs(repeat, [&] { STAGE_CHECK(cudaMemcpy(dst, src, copy_bytes, cudaMemcpyDeviceToDevice)); }));
  constexpr int kLaunches = 200;
  const Times launches = time_runs(repeat, [&] {
    for (int k = 0; k < kLaunches; ++k) empty_kernel<<<1, 32>>>();
  });
  row(out, "launch", 0, kLaunches, 0, Times{launches.median_ms / kLaunches, launches.min_ms / kLaunches});
  STAGE_CHECK(cudaFree(src));
  STAGE_CHECK(cudaFree(dst));

  uint32_t *k32 = nullptr, *s32 = nullptr, *values = nullptr, *order = nullptr;
  uint64_t *k64 = nullptr, *s64 = nullptr;
  STAGE_CHECK(cudaMalloc(&k32, n * sizeof(uint32_t)));
  STAGE_CHECK(cudaMalloc(&s32, n * sizeof(uint32_t)));
  STAGE_CHECK(cudaMalloc(&k64, n * sizeof(uint64_t)));
  STAGE_CHECK(cudaMalloc(&s64, n * sizeof(uint64_t)));
  STAGE_CHECK(cudaMalloc(&values, n * sizeof(uint32_t)));
  STAGE_CHECK(cudaMalloc(&order, n * sizeof(uint32_t)));
  for (int bits : {8, 16, 24, 30, 32, 48, 64}) {
    const uint64_t mask = bits == 64 ? ~0ull : (1ull << bits) - 1;
    random_keys_kernel<<<static_cast<unsigned>((n + 255) / 256), 256>>>(k32, k64, values, n, mask);
    STAGE_CHECK(cudaGetLastError());
    const Times t = bits <= 32 ? cub_sort(k32, s32, values, order, n, bits, repeat)
                               : cub_sort(k64, s64, values, order, n, bits, repeat);
    row(out, "cub_sort", bits, n, 0, t);
  }
  for (void* p : {static_cast<void*>(k32), static_cast<void*>(s32), static_cast<void*>(k64), static_cast<void*>(s64),
                  static_cast<void*>(values), static_cast<void*>(order)})
    STAGE_CHECK(cudaFree(p));
  if (out != stdout) std::fclose(out);
  return 0;
}
