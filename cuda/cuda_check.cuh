// CUDA plumbing shared by the .cu files (nvcc only; never included from g++-compiled code): the one checking
// macro every CUDA runtime call goes through, owning device buffers, and an event pair for kernel times.
//
// Errors: a failed call throws raycoh::Error("CUDA error in <call>: <message>"), which main() reports as a
// one-line error. Destructors cannot throw: a failed cudaFree / cudaEventDestroy there is printed to stderr.
// (No fmt in .cu files: its consteval format strings do not compile under nvcc 13.)
#pragma once

#include <cuda_runtime.h>

#include <cstddef>
#include <cstdio>
#include <string>

#include "core/error.h"

namespace raycoh::cuda {

inline void check_cuda(cudaError_t err, const char* call, const char* file, int line) {
  if (err != cudaSuccess)
    throw Error(std::string("CUDA error in ") + call + " (" + file + ":" + std::to_string(line) +
                "): " + cudaGetErrorString(err));
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
    RAYCOH_CUDA_CHECK(cudaEventSynchronize(stop_));
    float ms = 0.f;
    RAYCOH_CUDA_CHECK(cudaEventElapsedTime(&ms, start_, stop_));
    return ms;
  }

 private:
  cudaEvent_t start_ = nullptr, stop_ = nullptr;
};

}  // namespace raycoh::cuda
