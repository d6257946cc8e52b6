// The `cuda` tracer's hardware counters (counters=hw): CUPTI's range profiler around a trace or a device pass, every
// kernel launched in between one range (auto ranges, kernel replay), evaluated into tracers/hw_counters.h's
// quantities for the trace kernels (implemented in cuda/hw_profiler.cpp; plain C++, callable from g++ code).
//
// CUPTI (libcupti.so.13, which itself loads libnvperf_host.so) is opened at run time with dlopen, as NVML is in
// cuda/gpu_facts.cu: nothing links it, the build and every run without counters=hw are unchanged, and a machine
// without it gives the one line of hw_counters_unavailable() instead of a load failure.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "tracers/hw_counters.h"

namespace raycoh::cuda {

class HwProfiler {
 public:
  // Loads CUPTI and configures hw_metric_names() on device 0's current context (the caller has made it: the
  // DeviceTracer's upload). Never throws for a missing library, device or privilege: unavailable() says why.
  HwProfiler();
  ~HwProfiler();
  HwProfiler(const HwProfiler&) = delete;
  HwProfiler& operator=(const HwProfiler&) = delete;

  // The one line saying why counters cannot be read (hw_counters_unavailable), empty when they can.
  const std::string& unavailable() const { return unavailable_; }
  // Metrics this chip does not know (their quantities stay empty), comma-separated; empty when it knows all.
  const std::string& unknown_metrics() const { return unknown_; }

  // Opens a profiling session: each kernel launched until end() is replayed as often as its metrics need.
  void begin();
  // Closes it and evaluates every range: the trace kernels' counters, or nothing where the session failed (the
  // reason is printed once and the profiler reads nothing more).
  std::optional<HwCounters> end();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string unavailable_, unknown_;
};

}  // namespace raycoh::cuda
