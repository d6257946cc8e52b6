// Injected faults, to test that a failing device loses nothing: RAYCOH_INJECT_FAULT=<site>:<n> makes the n-th
// check of a site whose name contains <site> fail (n from 1). Sites are the CUDA runtime calls every CUDA call is
// checked through (cuda/cuda_check.cuh: e.g. `cudaMalloc` an allocation failure, `cudaGetLastError` a launch
// failure, `cudaEventSynchronize` a kernel past its time limit) and the experiment loop's `trace` (before each timed
// measurement of any tracer: a device fault where there is no device). Host code; off unless the variable is set.
#pragma once

#include <string>

namespace raycoh {

// True exactly once: at the n-th call whose `site` contains the configured site (RAYCOH_INJECT_FAULT, or
// set_fault_injection). Thread-safe.
bool inject_fault(const std::string& site);

// Replaces the configuration (tests): "<site>:<n>", or "" for none. Resets the count. Throws raycoh::Error on a
// malformed value.
void set_fault_injection(const std::string& spec);

}  // namespace raycoh
