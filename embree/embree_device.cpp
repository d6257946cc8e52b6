// Embree device creation and the one error callback; see embree_device.h.
#include "embree/embree_device.h"

#include <fmt/format.h>

#include "core/error.h"

namespace raycoh {
namespace {

// The first error Embree reported on this thread since the last embree_check(). Embree reports an error on the
// thread that made the failing API call, so a thread-local record pairs each error with its caller.
struct PendingError {
  RTCError code = RTC_ERROR_NONE;
  std::string message;
};
thread_local PendingError pending_error;

void record_error(void*, RTCError code, const char* message) {
  if (pending_error.code != RTC_ERROR_NONE) return;  // keep the first: later ones are usually consequences
  pending_error.code = code;
  pending_error.message = message ? message : "";
}

const char* error_name(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE:
      return "RTC_ERROR_NONE";
    case RTC_ERROR_UNKNOWN:
      return "RTC_ERROR_UNKNOWN";
    case RTC_ERROR_INVALID_ARGUMENT:
      return "RTC_ERROR_INVALID_ARGUMENT";
    case RTC_ERROR_INVALID_OPERATION:
      return "RTC_ERROR_INVALID_OPERATION";
    case RTC_ERROR_OUT_OF_MEMORY:
      return "RTC_ERROR_OUT_OF_MEMORY";
    case RTC_ERROR_UNSUPPORTED_CPU:
      return "RTC_ERROR_UNSUPPORTED_CPU";
    case RTC_ERROR_CANCELLED:
      return "RTC_ERROR_CANCELLED";
  }
  return "unknown RTCError";
}

// Owns the device so that it is released at exit after everything that retained it.
struct DeviceHolder {
  RTCDevice device = nullptr;
  DeviceHolder() {
    device = rtcNewDevice(nullptr);
    if (!device) {
      const RTCError code = rtcGetDeviceError(nullptr);
      throw Error(
          fmt::format("cannot create the Embree device ({}); Embree {} needs an x86-64 CPU with SSE2 "
                      "and enough memory",
                      error_name(code), RTC_VERSION_STRING));
    }
    rtcSetDeviceErrorFunction(device, record_error, nullptr);
  }
  ~DeviceHolder() {
    if (device) rtcReleaseDevice(device);
  }
};

}  // namespace

RTCDevice embree_device() {
  static DeviceHolder holder;
  return holder.device;
}

void embree_check(const std::string& what) { embree_check(what.c_str()); }

void embree_check(const char* what) {
  PendingError error = std::move(pending_error);
  pending_error = PendingError{};
  // rtcGetDeviceError also clears Embree's own per-thread code; it catches errors raised before the callback
  // was installed or by a device made elsewhere.
  const RTCError device_code = rtcGetDeviceError(embree_device());
  if (error.code == RTC_ERROR_NONE) error.code = device_code;
  if (error.code == RTC_ERROR_NONE) return;
  const std::string detail = fmt::format("{} while {}: {}", error_name(error.code), what,
                                         error.message.empty() ? "(no message)" : error.message);
  switch (error.code) {
    case RTC_ERROR_INVALID_ARGUMENT:
    case RTC_ERROR_INVALID_OPERATION:
      invariant_failed("Embree accepted the call", __FILE__, __LINE__, detail);
    case RTC_ERROR_OUT_OF_MEMORY:
      throw Error(
          fmt::format("Embree ran out of memory ({}); try a smaller scene or a machine with more memory", detail));
    default:
      throw Error(fmt::format("Embree failed: {}", detail));
  }
}

std::string embree_version() { return RTC_VERSION_STRING; }

}  // namespace raycoh
