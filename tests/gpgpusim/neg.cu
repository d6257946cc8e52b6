// Micro test of scripts/gpgpusim/patches/0005 (neg.f32 / neg.ftz.f32 / neg.f64 flip the sign bit): the results'
// bits against the host's negation on zeros of both signs, a subnormal (flushed to a signed zero by .ftz),
// NaN, infinity and ordinary values. Usage: neg (exit 0 when all agree).
#include <cuda_runtime.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>

__global__ void negate(const float* x, const double* y, int n, float* out, float* out_ftz, double* out64) {
  const int i = threadIdx.x;
  if (i >= n) return;
  asm("neg.f32 %0, %1;" : "=f"(out[i]) : "f"(x[i]));
  asm("neg.ftz.f32 %0, %1;" : "=f"(out_ftz[i]) : "f"(x[i]));
  asm("neg.f64 %0, %1;" : "=d"(out64[i]) : "d"(y[i]));
}

uint32_t bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}
uint64_t bits(double f) {
  uint64_t u;
  std::memcpy(&u, &f, 8);
  return u;
}

int main() {
  const float x[] = {0.f, -0.f, 1e-40f, -1e-40f, 1.5f, -2.25f, INFINITY, NAN};
  const double y[] = {0.0, -0.0, 1e-310, 1.5, -2.25, INFINITY, NAN, -NAN};
  const int n = 8;
  float *dx, *d, *dftz;
  double *dy, *d64;
  cudaMalloc(&dx, sizeof(x));
  cudaMalloc(&dy, sizeof(y));
  cudaMalloc(&d, sizeof(x));
  cudaMalloc(&dftz, sizeof(x));
  cudaMalloc(&d64, sizeof(y));
  cudaMemcpy(dx, x, sizeof(x), cudaMemcpyHostToDevice);
  cudaMemcpy(dy, y, sizeof(y), cudaMemcpyHostToDevice);
  negate<<<1, 32>>>(dx, dy, n, d, dftz, d64);
  float r[n], rftz[n];
  double r64[n];
  cudaMemcpy(r, d, sizeof(r), cudaMemcpyDeviceToHost);
  cudaMemcpy(rftz, dftz, sizeof(rftz), cudaMemcpyDeviceToHost);
  cudaMemcpy(r64, d64, sizeof(r64), cudaMemcpyDeviceToHost);
  int wrong = 0;
  for (int i = 0; i < n; ++i) {
    const float want = -x[i];
    const float want_ftz = std::fpclassify(x[i]) == FP_SUBNORMAL ? (x[i] > 0.f ? -0.f : 0.f) : -x[i];
    if (bits(r[i]) != bits(want)) ++wrong, std::printf("neg.f32 %08x: %08x\n", bits(x[i]), bits(r[i]));
    if (bits(rftz[i]) != bits(want_ftz)) ++wrong, std::printf("neg.ftz.f32 %08x: %08x\n", bits(x[i]), bits(rftz[i]));
    if (bits(r64[i]) != bits(-y[i]))
      ++wrong,
          std::printf("neg.f64 %016llx: %016llx\n", (unsigned long long)bits(y[i]), (unsigned long long)bits(r64[i]));
  }
  std::printf("%s: %d of %d negations wrong\n", wrong ? "FAIL" : "PASS", wrong, 3 * n);
  return wrong ? 1 : 0;
}
