// Micro test of scripts/gpgpusim/patches/0007 (directed rounding and fused fma): fma, mul, add and sub in .rn, .rz,
// .rm and .rp (f32, with .ftz as raycoh compiles, and f64), on operands whose exact result is not a float, against
// the host computing the same operation in the same rounding mode (fesetround; volatile operands, so that nothing
// is folded at compile time in the default mode). Usage: rounding (exit 0 when all agree).
#include <cuda_runtime.h>

#include <cfenv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>

constexpr int kOps = 4, kModes = 4, kN = 8;

__global__ void compute(const float* a, const float* b, const float* c, const double* x, float* out, double* out64) {
  const int i = threadIdx.x;
  if (i >= kN) return;
  float* o = out + i * kOps * kModes;
  o[0] = __fmaf_rn(a[i], b[i], c[i]);
  o[1] = __fmaf_rz(a[i], b[i], c[i]);
  o[2] = __fmaf_rd(a[i], b[i], c[i]);
  o[3] = __fmaf_ru(a[i], b[i], c[i]);
  o[4] = __fmul_rn(a[i], b[i]);
  o[5] = __fmul_rz(a[i], b[i]);
  o[6] = __fmul_rd(a[i], b[i]);
  o[7] = __fmul_ru(a[i], b[i]);
  o[8] = __fadd_rn(a[i], c[i]);
  o[9] = __fadd_rz(a[i], c[i]);
  o[10] = __fadd_rd(a[i], c[i]);
  o[11] = __fadd_ru(a[i], c[i]);
  o[12] = __fsub_rn(a[i], c[i]);
  o[13] = __fsub_rz(a[i], c[i]);
  o[14] = __fsub_rd(a[i], c[i]);
  o[15] = __fsub_ru(a[i], c[i]);
  double* p = out64 + i * 2;
  p[0] = __fma_rd(x[i], x[i], x[i] * 0.5);
  p[1] = __dmul_ru(x[i], x[i]);
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

float host(int op, int mode, volatile float a, volatile float b, volatile float c) {
  const int modes[kModes] = {FE_TONEAREST, FE_TOWARDZERO, FE_DOWNWARD, FE_UPWARD};
  std::fesetround(modes[mode]);
  volatile float r = op == 0 ? std::fmaf(a, b, c) : op == 1 ? a * b : op == 2 ? a + c : a - c;
  std::fesetround(FE_TONEAREST);
  return r;
}

int main() {
  const float a[kN] = {1.f / 3.f, -1.f / 3.f, 1.1f, 3.0e-3f, -7.77f, 1e10f, 0.1f, 1.f};
  const float b[kN] = {3.f, 3.f, 1.3f, 7.1e-2f, 0.3f, 1e-10f, 0.1f, 1.f};
  const float c[kN] = {-1.f, 1.f, 1e-8f, -2.2e-4f, 5.f, -1.f, 0.01f, 6e-8f};
  const double x[kN] = {1.0 / 3.0, -0.1, 1.1, 3e-3, -7.77, 1e10, 0.1, 1.0};
  float *da, *db, *dc, *dout;
  double *dx, *dout64;
  cudaMalloc(&da, sizeof(a));
  cudaMalloc(&db, sizeof(b));
  cudaMalloc(&dc, sizeof(c));
  cudaMalloc(&dx, sizeof(x));
  cudaMalloc(&dout, sizeof(float) * kN * kOps * kModes);
  cudaMalloc(&dout64, sizeof(double) * kN * 2);
  cudaMemcpy(da, a, sizeof(a), cudaMemcpyHostToDevice);
  cudaMemcpy(db, b, sizeof(b), cudaMemcpyHostToDevice);
  cudaMemcpy(dc, c, sizeof(c), cudaMemcpyHostToDevice);
  cudaMemcpy(dx, x, sizeof(x), cudaMemcpyHostToDevice);
  compute<<<1, 32>>>(da, db, dc, dx, dout, dout64);
  float out[kN * kOps * kModes];
  double out64[kN * 2];
  cudaMemcpy(out, dout, sizeof(out), cudaMemcpyDeviceToHost);
  cudaMemcpy(out64, dout64, sizeof(out64), cudaMemcpyDeviceToHost);
  const char* names[kOps] = {"fma", "mul", "add", "sub"};
  const char* modes[kModes] = {"rn", "rz", "rm", "rp"};
  int wrong = 0, total = 0;
  for (int i = 0; i < kN; ++i)
    for (int op = 0; op < kOps; ++op)
      for (int m = 0; m < kModes; ++m, ++total) {
        const float want = host(op, m, a[i], b[i], c[i]), got = out[(i * kOps + op) * kModes + m];
        if (bits(want) != bits(got))
          ++wrong, std::printf("%s.%s.f32 #%d: %08x, host %08x\n", names[op], modes[m], i, bits(got), bits(want));
      }
  for (int i = 0; i < kN; ++i) {
    volatile double v = x[i], h = x[i] * 0.5;
    std::fesetround(FE_DOWNWARD);
    volatile double f = std::fma(v, v, h);
    std::fesetround(FE_UPWARD);
    volatile double g = v * v;
    std::fesetround(FE_TONEAREST);
    total += 2;
    if (bits(double(f)) != bits(out64[2 * i])) ++wrong, std::printf("fma.rm.f64 #%d differs\n", i);
    if (bits(double(g)) != bits(out64[2 * i + 1])) ++wrong, std::printf("mul.rp.f64 #%d differs\n", i);
  }
  std::printf("%s: %d of %d results wrong\n", wrong ? "FAIL" : "PASS", wrong, total);
  return wrong ? 1 : 0;
}
