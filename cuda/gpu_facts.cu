// What identifies the GPU of a measured row (cuda/cuda_device.h: device_facts, device_clocks): the CUDA driver and
// runtime versions from the runtime, the NVIDIA driver's version and the current SM and memory clocks from NVML.
// NVML is opened at run time (libnvidia-ml.so.1, installed with the driver), so that a build without it, a machine
// without a GPU and GPGPU-Sim give empty facts instead of a link or load failure.
#include <cuda_runtime.h>
#include <dlfcn.h>

#include <mutex>
#include <string>

#include "cuda/cuda_device.h"

namespace raycoh::cuda {
namespace {

// The NVML entry points used, declared as NVML's C API has them (nvmlReturn_t 0 = success).
using NvmlDevice = void*;
using NvmlInit = int (*)();
using NvmlHandleByPci = int (*)(const char*, NvmlDevice*);
using NvmlClockInfo = int (*)(NvmlDevice, int, unsigned*);
using NvmlDriverVersion = int (*)(char*, unsigned);
constexpr int kNvmlClockSm = 1, kNvmlClockMem = 2;

struct Nvml {
  NvmlDevice device = nullptr;
  NvmlClockInfo clock_info = nullptr;
  std::string driver;
};

// NVML opened once, with device 0's handle (by its PCI bus id, the same GPU as CUDA's device 0); empty when any
// step fails.
const Nvml& nvml() {
  static Nvml n;
  static std::once_flag once;
  std::call_once(once, [] {
    void* lib = dlopen("libnvidia-ml.so.1", RTLD_NOW | RTLD_LOCAL);
    if (!lib) return;
    auto init = reinterpret_cast<NvmlInit>(dlsym(lib, "nvmlInit_v2"));
    auto by_pci = reinterpret_cast<NvmlHandleByPci>(dlsym(lib, "nvmlDeviceGetHandleByPciBusId_v2"));
    auto clocks = reinterpret_cast<NvmlClockInfo>(dlsym(lib, "nvmlDeviceGetClockInfo"));
    auto version = reinterpret_cast<NvmlDriverVersion>(dlsym(lib, "nvmlSystemGetDriverVersion"));
    char bus[64] = {};
    if (!init || !by_pci || !clocks || init() != 0 || cudaDeviceGetPCIBusId(bus, sizeof bus, 0) != cudaSuccess) {
      cudaGetLastError();
      return;
    }
    if (by_pci(bus, &n.device) != 0) return;
    n.clock_info = clocks;
    char v[96] = {};
    if (version && version(v, sizeof v) == 0) n.driver = v;
  });
  return n;
}

std::string version_text(int v) { return std::to_string(v / 1000) + "." + std::to_string(v % 1000 / 10); }

}  // namespace

DeviceFacts device_facts() {
  DeviceFacts f;
  if (device_count() == 0) return f;
  cudaDeviceProp prop{};
  if (cudaGetDeviceProperties(&prop, 0) == cudaSuccess) f.sms = prop.multiProcessorCount;
#ifdef RAYCOH_CUDA_SIM
  // GPGPU-Sim's runtime has neither a driver nor NVML to ask (docs/gpgpusim.md).
  f.driver = f.runtime = "GPGPU-Sim";
  return f;
#endif
  int v = 0;
  if (cudaDriverGetVersion(&v) == cudaSuccess) f.driver = "CUDA " + version_text(v);
  if (cudaRuntimeGetVersion(&v) == cudaSuccess) f.runtime = version_text(v);
  const Nvml& n = nvml();
  if (!n.driver.empty()) f.driver = n.driver + " (" + f.driver + ")";
  cudaGetLastError();
  return f;
}

DeviceClocks device_clocks() {
  DeviceClocks c;
#ifdef RAYCOH_CUDA_SIM
  return c;
#endif
  if (device_count() == 0) return c;
  const Nvml& n = nvml();
  unsigned mhz = 0;
  if (n.clock_info && n.clock_info(n.device, kNvmlClockSm, &mhz) == 0) c.sm_mhz = static_cast<int>(mhz);
  if (n.clock_info && n.clock_info(n.device, kNvmlClockMem, &mhz) == 0) c.mem_mhz = static_cast<int>(mhz);
  return c;
}

}  // namespace raycoh::cuda
