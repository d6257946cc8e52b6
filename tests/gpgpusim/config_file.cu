// Micro test of scripts/gpgpusim/patches/0001 (GPGPUSIM_CONFIG_FILE): run from a folder without a
// gpgpusim.config, the simulator must read the per-run configuration that scripts/gpgpusim-run names, here with
// `--sms N`: the device reports N SMs, and a kernel runs. Usage: config_file N (exit 0 when both hold).
#include <cuda_runtime.h>

#include <cstdio>
#include <cstdlib>

__global__ void square(int* v) { v[threadIdx.x] = static_cast<int>(threadIdx.x * threadIdx.x); }

int main(int argc, char** argv) {
  const int want = argc > 1 ? std::atoi(argv[1]) : 0;
  cudaDeviceProp prop{};
  if (cudaGetDeviceProperties(&prop, 0) != cudaSuccess) return std::puts("FAIL: no device"), 1;
  int* d = nullptr;
  int h[64] = {};
  cudaMalloc(&d, sizeof(h));
  square<<<1, 64>>>(d);
  cudaMemcpy(h, d, sizeof(h), cudaMemcpyDeviceToHost);
  cudaFree(d);
  const bool ok = prop.multiProcessorCount == want && h[63] == 63 * 63;
  std::printf("%s: %d SMs (want %d), v[63] = %d\n", ok ? "PASS" : "FAIL", prop.multiProcessorCount, want, h[63]);
  return ok ? 0 : 1;
}
