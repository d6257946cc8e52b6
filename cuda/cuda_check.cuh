// CUDA plumbing shared by the .cu files (nvcc only; never included from g++-compiled code): the one checking
// macro every CUDA runtime call goes through, owning device buffers, and an event pair for kernel times.
//
// Errors: a failed call throws raycoh::DeviceFault("CUDA error in <call>: <message>"), which the experiment loops
// name with their scene, method and stage and main() reports as a one-line error (exit 1). Destructors cannot
// throw: a failed cudaFree / cudaEventDestroy there is printed to stderr. Every check is a site of injected faults
// (core/fault_injection.h), and waiting for a kernel honours RAYCOH_KERNEL_TIMEOUT_S (EventTimer::elapsed_ms).
// (No fmt in .cu files: its consteval format strings do not compile under nvcc 13.)
#pragma once

#include <cuda_runtime.h>

#include <chrono>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/error.h"
#include "core/fault_injection.h"

namespace raycoh::cuda {

// The error an injected fault at `call` stands for: an allocation, a launch, or a kernel that did not finish.
inline cudaError_t injected_error(const std::string& call) {
  if (call.find("cudaMalloc") != std::string::npos) return cudaErrorMemoryAllocation;
  if (call.find("Synchronize") != std::string::npos) return cudaErrorLaunchTimeout;
  return cudaErrorLaunchFailure;
}

inline void check_cuda(cudaError_t err, const char* call, const char* file, int line) {
  const bool injected = err == cudaSuccess && inject_fault(call);
  if (injected) err = injected_error(call);
  if (err != cudaSuccess)
    throw DeviceFault(std::string("CUDA error in ") + call + " (" + file + ":" + std::to_string(line) +
                      "): " + cudaGetErrorString(err) + (injected ? " (injected: RAYCOH_INJECT_FAULT)" : ""));
}

// RAYCOH_KERNEL_TIMEOUT_S: seconds a wait for a kernel may last before the run stops with a device fault (unset or
// 0: no limit; a display GPU's own watchdog still applies).
inline double kernel_timeout_s() {
  const char* env = std::getenv("RAYCOH_KERNEL_TIMEOUT_S");
  return env ? std::atof(env) : 0.0;
}

// Waits for `event` within the time limit: cudaEventSynchronize, or polling cudaEventQuery under a limit.
inline void wait_event(cudaEvent_t event) {
  const double limit = kernel_timeout_s();
  if (limit <= 0) {
    check_cuda(cudaEventSynchronize(event), "cudaEventSynchronize(stop_)", __FILE__, __LINE__);
    return;
  }
  const auto t0 = std::chrono::steady_clock::now();
  for (;;) {
    const cudaError_t e = cudaEventQuery(event);
    if (e != cudaErrorNotReady) return check_cuda(e, "cudaEventQuery(stop_)", __FILE__, __LINE__);
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > limit)
      throw DeviceFault("a kernel ran past its time limit of " + std::to_string(limit) +
                        " s (RAYCOH_KERNEL_TIMEOUT_S); the device is left running it until the process exits");
  }
}

inline void report_cuda(cudaError_t err, const char* call) {
  if (err != cudaSuccess) std::fprintf(stderr, "raycoh: CUDA error in %s: %s\n", call, cudaGetErrorString(err));
}

}  // namespace raycoh::cuda

#define RAYCOH_CUDA_CHECK(call) ::raycoh::cuda::check_cuda((call), #call, __FILE__, __LINE__)
// After a kernel launch: configuration errors show up in cudaGetLastError, faults at the next synchronisation.
#define RAYCOH_CUDA_CHECK_LAUNCH() RAYCOH_CUDA_CHECK(cudaGetLastError())

namespace raycoh::cuda {

// Device array of T that grows on demand and never shrinks; contents are not kept across a growth.
template <class T>
class DeviceBuffer {
 public:
  DeviceBuffer() = default;
  explicit DeviceBuffer(size_t n) { reserve(n); }
  ~DeviceBuffer() { release(); }
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
  DeviceBuffer(DeviceBuffer&& o) noexcept : ptr_(o.ptr_), capacity_(o.capacity_) {
    o.ptr_ = nullptr;
    o.capacity_ = 0;
  }

  // At least n elements (and never a null pointer, so that empty arrays can still be passed to kernels).
  void reserve(size_t n) {
    if (n <= capacity_ && ptr_) return;
    release();
    const size_t want = n ? n : 1;
    RAYCOH_CUDA_CHECK(cudaMalloc(&ptr_, sizeof(T) * want));
    capacity_ = want;
  }
  void upload(const T* host, size_t n) {
    reserve(n);
    if (n) RAYCOH_CUDA_CHECK(cudaMemcpy(ptr_, host, sizeof(T) * n, cudaMemcpyHostToDevice));
  }
  void download(T* host, size_t n) const {
    if (n) RAYCOH_CUDA_CHECK(cudaMemcpy(host, ptr_, sizeof(T) * n, cudaMemcpyDeviceToHost));
  }
  void zero(size_t n) {
    reserve(n);
    if (n) RAYCOH_CUDA_CHECK(cudaMemset(ptr_, 0, sizeof(T) * n));
  }
  T* get() const { return ptr_; }
  size_t capacity() const { return capacity_; }

 private:
  void release() {
    if (ptr_) report_cuda(cudaFree(ptr_), "cudaFree");
    ptr_ = nullptr;
    capacity_ = 0;
  }
  T* ptr_ = nullptr;
  size_t capacity_ = 0;
};

// Start/stop events on the default stream; elapsed_ms() waits for the stop event.
class EventTimer {
 public:
  EventTimer() {
    RAYCOH_CUDA_CHECK(cudaEventCreate(&start_));
    RAYCOH_CUDA_CHECK(cudaEventCreate(&stop_));
  }
  ~EventTimer() {
    report_cuda(cudaEventDestroy(start_), "cudaEventDestroy");
    report_cuda(cudaEventDestroy(stop_), "cudaEventDestroy");
  }
  EventTimer(const EventTimer&) = delete;
  EventTimer& operator=(const EventTimer&) = delete;
  void start() { RAYCOH_CUDA_CHECK(cudaEventRecord(start_)); }
  void stop() { RAYCOH_CUDA_CHECK(cudaEventRecord(stop_)); }
  float elapsed_ms() const {
    wait_event(stop_);
    float ms = 0.f;
    RAYCOH_CUDA_CHECK(cudaEventElapsedTime(&ms, start_, stop_));
    return ms;
  }

 private:
  cudaEvent_t start_ = nullptr, stop_ = nullptr;
};

}  // namespace raycoh::cuda
