// The one adapter for Embree 3 device creation and error handling.
//
// Every Embree call in raycoh goes through a device made here, and every Embree error goes through one error
// callback (Embree's recommended pattern, rtcSetDeviceErrorFunction). The callback only records the error:
// throwing across Embree's C API, possibly from inside its TBB tasks, is not safe. Callers then call
// embree_check() right after an API call, which turns the recorded error into
//   - raycoh::Error for what the user can act on (out of memory, unsupported CPU, a build that fails on the
//     input, e.g. Embree's "depth limit reached"), and
//   - an invariant failure (message with code and text, then abort) for misuse of the API by raycoh itself
//     (RTC_ERROR_INVALID_ARGUMENT, RTC_ERROR_INVALID_OPERATION).
//
// Parameters: none. The device uses Embree's defaults (all hardware threads through TBB, no thread pinning),
// so that it shares TBB's thread pool with raycoh's own parallel loops and honours tbb::global_control.
#pragma once

#include <embree3/rtcore.h>

#include <string>

namespace raycoh {

// The process-wide Embree device, created on first use (thread-safe). Creating one device per scene or tracer
// would start one thread pool each; Embree devices are meant to be shared.
RTCDevice embree_device();

// Throws raycoh::Error or fails an invariant if an Embree call on this thread since the last check reported an
// error; `what` names the operation for the message ("building the BVH of scene 'sibenik'").
void embree_check(const char* what);
void embree_check(const std::string& what);

// "3.13.5", for provenance records.
std::string embree_version();

}  // namespace raycoh
