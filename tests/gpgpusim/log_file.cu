// Micro test of scripts/gpgpusim/patches/0002 (the simulator's messages go to GPGPUSIM_LOG_FILE): the program's
// stdout must hold exactly its own two lines, the device printf's and the host's, and none of the simulator's
// configuration, PTX-loading and kernel messages (scripts/gpgpusim-micro-tests compares it byte for byte).
#include <cuda_runtime.h>

#include <cstdio>

__global__ void hello(int x) {
  if (threadIdx.x == 0) printf("device says %d\n", x);
}

int main() {
  hello<<<1, 32>>>(7);
  if (cudaDeviceSynchronize() != cudaSuccess) return 1;
  std::printf("host says %d\n", 8);
  return 0;
}
