// Micro test of scripts/gpgpusim/patches/0004 (prmt: __byte_perm, whose selector nvcc masks with 0x7777, and
// prmt.b32 itself with sign selectors and every mode): source words with their top bit set (the case the
// simulator got wrong) and without, against the PTX rule computed on the host. Usage: prmt (exit 0 when all
// agree).
#include <cuda_runtime.h>

#include <cstdint>
#include <cstdio>

constexpr int kModes = 8;  // __byte_perm, default, f4e, b4e, rc8, ecl, ecr, rc16

__global__ void permute(const uint32_t* a, const uint32_t* b, const uint32_t* sel, int n, uint32_t* out) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  uint32_t* d = out + i * kModes;
  d[0] = __byte_perm(a[i], b[i], sel[i]);
  asm("prmt.b32 %0, %1, %2, %3;" : "=r"(d[1]) : "r"(a[i]), "r"(b[i]), "r"(sel[i]));
  asm("prmt.b32.f4e %0, %1, %2, %3;" : "=r"(d[2]) : "r"(a[i]), "r"(b[i]), "r"(sel[i]));
  asm("prmt.b32.b4e %0, %1, %2, %3;" : "=r"(d[3]) : "r"(a[i]), "r"(b[i]), "r"(sel[i]));
  asm("prmt.b32.rc8 %0, %1, %2, %3;" : "=r"(d[4]) : "r"(a[i]), "r"(b[i]), "r"(sel[i]));
  asm("prmt.b32.ecl %0, %1, %2, %3;" : "=r"(d[5]) : "r"(a[i]), "r"(b[i]), "r"(sel[i]));
  asm("prmt.b32.ecr %0, %1, %2, %3;" : "=r"(d[6]) : "r"(a[i]), "r"(b[i]), "r"(sel[i]));
  asm("prmt.b32.rc16 %0, %1, %2, %3;" : "=r"(d[7]) : "r"(a[i]), "r"(b[i]), "r"(sel[i]));
}

// The PTX ISA's definition: byte k of {b, a} is byte k of a for k < 4, byte k - 4 of b otherwise.
uint32_t byte_of(uint32_t a, uint32_t b, int k) { return ((k < 4 ? a : b) >> (8 * (k & 3))) & 0xFFu; }

uint32_t reference(uint32_t a, uint32_t b, uint32_t sel, int mode) {
  if (mode == 0) return reference(a, b, sel & 0x7777u, 1);  // __byte_perm: nvcc masks the selector
  uint32_t d = 0;
  const int c = static_cast<int>(sel & 3u);
  for (int i = 0; i < 4; ++i) {
    uint32_t byte = 0;
    if (mode == 1) {
      const uint32_t nibble = (sel >> (4 * i)) & 0xFu;
      byte = byte_of(a, b, static_cast<int>(nibble & 7u));
      if (nibble & 8u) byte = (byte & 0x80u) ? 0xFFu : 0u;
    } else {
      const int index[kModes] = {0, 0, c + i, (c - i) & 7, c, i > c ? i : c, i < c ? i : c, (c & 1) * 2 + (i & 1)};
      byte = byte_of(a, b, index[mode]);
    }
    d |= byte << (8 * i);
  }
  return d;
}

int main() {
  const uint32_t words[][2] = {{0x8C3A5F91u, 0x4B000000u}, {0x12345678u, 0x9ABCDEF0u}, {0xFFFFFFFFu, 0x0u}};
  const uint32_t selectors[] = {0x7440u, 0x7441u, 0x7442u, 0x7443u, 0x3210u, 0x7654u, 0x8888u, 0xBA98u,
                                0xFEDCu, 0x0123u, 0x5140u, 0x1u,    0x2u,    0x3u,    0x0u};
  const int per = sizeof(selectors) / sizeof(selectors[0]);
  const int n = 3 * per;
  uint32_t a[n], b[n], s[n], out[n * kModes];
  for (int i = 0; i < n; ++i) a[i] = words[i / per][0], b[i] = words[i / per][1], s[i] = selectors[i % per];
  uint32_t *da, *db, *ds, *dout;
  cudaMalloc(&da, sizeof(a));
  cudaMalloc(&db, sizeof(b));
  cudaMalloc(&ds, sizeof(s));
  cudaMalloc(&dout, sizeof(out));
  cudaMemcpy(da, a, sizeof(a), cudaMemcpyHostToDevice);
  cudaMemcpy(db, b, sizeof(b), cudaMemcpyHostToDevice);
  cudaMemcpy(ds, s, sizeof(s), cudaMemcpyHostToDevice);
  permute<<<1, 64>>>(da, db, ds, n, dout);
  cudaMemcpy(out, dout, sizeof(out), cudaMemcpyDeviceToHost);
  int wrong = 0;
  for (int i = 0; i < n; ++i)
    for (int m = 0; m < kModes; ++m) {
      const uint32_t want = reference(a[i], b[i], s[i], m);
      if (out[i * kModes + m] != want && ++wrong <= 5)
        std::printf("a %08x b %08x sel %04x mode %d: %08x, want %08x\n", a[i], b[i], s[i], m, out[i * kModes + m],
                    want);
    }
  std::printf("%s: %d of %d prmt results wrong\n", wrong ? "FAIL" : "PASS", wrong, n * kModes);
  return wrong ? 1 : 0;
}
