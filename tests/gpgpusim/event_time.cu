// Micro test of scripts/gpgpusim/patches/0003 (CUDA event times): a kernel between two events takes more than
// 0 ms in functional mode (the simulator's wall time) and in performance mode (simulated cycles / core clock,
// GPGPU_SIM_EVENT_CYCLES=1); two events with nothing between them take less than the kernel.
// Usage: event_time (exit 0 when both hold).
#include <cuda_runtime.h>

#include <cstdio>

__global__ void spin(float* v, int steps) {
  float x = static_cast<float>(threadIdx.x);
  for (int i = 0; i < steps; ++i) x = x * 0.999f + 1.f;
  v[blockIdx.x * blockDim.x + threadIdx.x] = x;
}

int main() {
  float* d = nullptr;
  cudaMalloc(&d, 64 * 128 * sizeof(float));
  cudaEvent_t a, b, c;
  cudaEventCreate(&a);
  cudaEventCreate(&b);
  cudaEventCreate(&c);
  cudaEventRecord(a);
  spin<<<64, 128>>>(d, 200);
  cudaEventRecord(b);
  cudaEventRecord(c);
  cudaEventSynchronize(c);
  float kernel_ms = -1.f, empty_ms = -1.f;
  cudaEventElapsedTime(&kernel_ms, a, b);
  cudaEventElapsedTime(&empty_ms, b, c);
  cudaFree(d);
  const bool ok = kernel_ms > 0.f && empty_ms >= 0.f && empty_ms < kernel_ms;
  std::printf("%s: kernel %.6f ms, nothing %.6f ms\n", ok ? "PASS" : "FAIL", kernel_ms, empty_ms);
  return ok ? 0 : 1;
}
