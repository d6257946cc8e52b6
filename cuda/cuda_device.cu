// Device discovery (device_count, device_name) and the one-call closest-hit helper of cuda/cuda_device.h, which runs
// the one-thread-per-ray kernel of cuda/trace_kernels.cu.
// (No fmt here: its consteval format strings do not compile under nvcc 13.)
#include <cuda_runtime.h>

#include <cstdlib>
#include <string>

#include "cuda/cuda_check.cuh"
#include "cuda/cuda_device.h"
#include "cuda/trace_kernels.h"

namespace raycoh::cuda {

int device_count() {
  int n = 0;
  if (cudaGetDeviceCount(&n) != cudaSuccess) {
    cudaGetLastError();  // clear the "no device" error; any error means no usable GPU
    return 0;
  }
  return n;
}

std::string device_name() {
  if (device_count() == 0) return "";
  cudaDeviceProp prop{};
  if (cudaGetDeviceProperties(&prop, 0) != cudaSuccess) return "";
#ifdef RAYCOH_CUDA_SIM
  // Built for GPGPU-Sim (RAYCOH_CUDA_SIM, docs/gpgpusim.md): every figure of this device is simulated, never
  // measured on hardware; in functional mode (PTX_SIM_MODE_FUNC=1, scripts/gpgpusim-run's default) no cycles are
  // simulated and CUDA event times are the simulator's own wall time.
  const char* functional = std::getenv("PTX_SIM_MODE_FUNC");
  const std::string label = functional && std::string(functional) == "1"
                                ? "simulated, functional mode (times are the simulator's wall time): "
                                : "simulated: ";
#else
  const std::string label;
#endif
  return label + std::string(prop.name) + " (sm_" + std::to_string(prop.major) + std::to_string(prop.minor) + ", " +
         std::to_string(prop.multiProcessorCount) + " SMs)";
}

long long device_resident_threads() {
  if (device_count() == 0) return 0;
  cudaDeviceProp prop{};
  if (cudaGetDeviceProperties(&prop, 0) != cudaSuccess) return 0;
  return static_cast<long long>(prop.multiProcessorCount) * prop.maxThreadsPerMultiProcessor;
}

void trace_closest(const BvhView& bvh, const Ray* rays, size_t count, Hit* hits, float* kernel_ms) {
  DeviceTracer tracer(bvh);
  TraceLaunch launch;
  launch.kernel = TraceKernel::Simple;
  tracer.trace(rays, nullptr, count, hits, launch);
  if (kernel_ms) *kernel_ms = tracer.last_kernel_ms();
}

}  // namespace raycoh::cuda
