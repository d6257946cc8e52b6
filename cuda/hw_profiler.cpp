// CUPTI's range profiler (CUDA 12.6 and later: cupti_range_profiler.h, cupti_profiler_host.h) behind
// cuda/hw_profiler.h. The library is opened with dlopen and every entry point taken with dlsym, typed from the
// toolkit's own declarations (decltype), so that nothing links libcupti and a machine without it still runs.
//
// Setup, once per tracer: cuptiProfilerInitialize; the chip's name and the context's counter availability; the host
// object, which checks each metric name (a name this chip lacks is left out, its quantity empty) and makes the
// configuration image. A session (begin .. end) enables the range profiler on the context, sizes and initialises a
// counter-data image for kMaxRanges ranges, sets the configuration with auto ranges (one per kernel) and kernel
// replay (CUPTI replays each kernel, restoring the memory it writes, once per pass the metrics need), starts; end()
// stops, decodes, evaluates every range with cuptiProfilerHostEvaluateToGpuValues and disables the profiler again.
#include "cuda/hw_profiler.h"

#include <cuda.h>
#include <cuda_runtime.h>
#include <cupti_profiler_host.h>
#include <cupti_profiler_target.h>
#include <cupti_range_profiler.h>
#include <cupti_result.h>
#include <cupti_target.h>
#include <dlfcn.h>

#include <cstdint>
#include <cstdio>
#include <mutex>
#include <set>
#include <vector>

#include "cuda/cuda_device.h"

namespace raycoh::cuda {
namespace {

constexpr size_t kMaxRanges = 256;  // kernels in one session: a device pass with a 64-bit sort launches about 30

// Every CUPTI entry point used.
#define RAYCOH_CUPTI_ENTRIES(X)                   \
  X(cuptiGetResultString)                         \
  X(cuptiProfilerInitialize)                      \
  X(cuptiDeviceGetChipName)                       \
  X(cuptiProfilerGetCounterAvailability)          \
  X(cuptiProfilerHostInitialize)                  \
  X(cuptiProfilerHostDeinitialize)                \
  X(cuptiProfilerHostGetMetricProperties)         \
  X(cuptiProfilerHostConfigAddMetrics)            \
  X(cuptiProfilerHostGetConfigImageSize)          \
  X(cuptiProfilerHostGetConfigImage)              \
  X(cuptiProfilerHostGetNumOfPasses)              \
  X(cuptiProfilerHostEvaluateToGpuValues)         \
  X(cuptiRangeProfilerEnable)                     \
  X(cuptiRangeProfilerDisable)                    \
  X(cuptiRangeProfilerGetCounterDataSize)         \
  X(cuptiRangeProfilerCounterDataImageInitialize) \
  X(cuptiRangeProfilerSetConfig)                  \
  X(cuptiRangeProfilerStart)                      \
  X(cuptiRangeProfilerStop)                       \
  X(cuptiRangeProfilerDecodeData)                 \
  X(cuptiRangeProfilerGetCounterDataInfo)         \
  X(cuptiRangeProfilerCounterDataGetRangeInfo)

struct Cupti {
#define RAYCOH_CUPTI_POINTER(f) decltype(&::f) f = nullptr;
  RAYCOH_CUPTI_ENTRIES(RAYCOH_CUPTI_POINTER)
#undef RAYCOH_CUPTI_POINTER
};

// libcupti opened once; nullptr (and why in `error`) when it cannot be loaded or lacks an entry point.
const Cupti* load_cupti(std::string& error) {
  static Cupti c;
  static std::string why;
  static bool loaded = false;
  static std::once_flag once;
  std::call_once(once, [] {
    void* lib = nullptr;
    for (const char* name : {"libcupti.so.13", "libcupti.so"})
      if ((lib = dlopen(name, RTLD_NOW | RTLD_LOCAL)) != nullptr) break;
    if (!lib) {
      const char* e = dlerror();
      why = std::string("dlopen libcupti.so.13: ") + (e ? e : "not found") +
            " (put the CUDA toolkit's lib or gpu-bundle/cupti on LD_LIBRARY_PATH)";
      return;
    }
#define RAYCOH_CUPTI_LOAD(f)                                                       \
  c.f = reinterpret_cast<decltype(c.f)>(dlsym(lib, #f));                           \
  if (!c.f) {                                                                      \
    why = "libcupti has no " #f " (the range profiler needs CUPTI 12.6 or later)"; \
    return;                                                                        \
  }
    RAYCOH_CUPTI_ENTRIES(RAYCOH_CUPTI_LOAD)
#undef RAYCOH_CUPTI_LOAD
    loaded = true;
  });
  error = why;
  return loaded ? &c : nullptr;
}

// The driver context the runtime made current for device 0 (CUPTI works on driver contexts), from libcuda.so.1,
// which the CUDA runtime has loaded already.
CUcontext current_context() {
  using GetCurrent = CUresult (*)(CUcontext*);
  void* lib = dlopen("libcuda.so.1", RTLD_NOW | RTLD_LOCAL);
  const auto get = lib ? reinterpret_cast<GetCurrent>(dlsym(lib, "cuCtxGetCurrent")) : nullptr;
  CUcontext ctx = nullptr;
  cudaFree(nullptr);  // the runtime makes device 0's primary context current
  cudaGetLastError();
  if (!get || get(&ctx) != CUDA_SUCCESS) return nullptr;
  return ctx;
}

// A CUPTI parameter struct: zeroed, with its size set (what every CUPTI call checks).
template <class P>
P make_params(size_t size) {
  P p{};
  p.structSize = size;
  return p;
}

// Prints a line once per process (a run makes a tracer per scene).
void print_once(const std::string& line) {
  static std::mutex m;
  static std::set<std::string> printed;
  const std::lock_guard<std::mutex> lock(m);
  if (printed.insert(line).second) std::fprintf(stderr, "%s\n", line.c_str());
}

}  // namespace

struct HwProfiler::Impl {
  const Cupti* c = nullptr;
  CUcontext ctx = nullptr;
  std::string chip;
  std::vector<uint8_t> availability, config, data;
  CUpti_Profiler_Host_Object* host = nullptr;
  CUpti_RangeProfiler_Object* range = nullptr;  // while a session is open
  std::vector<std::string> names;               // the metrics the chip knows
  std::vector<const char*> cnames;
  size_t passes = 0;
  bool failed = false;
  HwCounterConditions cond;

  // Whether r is success; otherwise the first failure is kept in cond.
  bool ok(CUptiResult r, const char* call) {
    if (r == CUPTI_SUCCESS) return true;
    if (cond.cupti_status == 0) {
      cond.cupti_status = static_cast<int>(r);
      cond.cupti_call = call;
      const char* text = nullptr;
      if (c->cuptiGetResultString(r, &text) == CUPTI_SUCCESS && text) cond.cupti_message = text;
    }
    return false;
  }

  bool setup(std::string& unknown);
  bool configure(std::string& unknown);
  bool open_session();
  bool close_session(std::vector<HwRange>& ranges);
  void disable();
};

// The profiler interface, the chip and what its counters can do on this context.
bool HwProfiler::Impl::setup(std::string& unknown) {
  auto init = make_params<CUpti_Profiler_Initialize_Params>(CUpti_Profiler_Initialize_Params_STRUCT_SIZE);
  if (!ok(c->cuptiProfilerInitialize(&init), "cuptiProfilerInitialize")) return false;
  ctx = current_context();
  if (!ctx) {
    cond.cupti_status = -1;
    cond.cupti_call = "cuCtxGetCurrent";
    cond.cupti_message = "no current CUDA context";
    return false;
  }
  auto name = make_params<CUpti_Device_GetChipName_Params>(CUpti_Device_GetChipName_Params_STRUCT_SIZE);
  name.deviceIndex = 0;
  if (!ok(c->cuptiDeviceGetChipName(&name), "cuptiDeviceGetChipName")) return false;
  chip = name.pChipName;
  auto avail = make_params<CUpti_Profiler_GetCounterAvailability_Params>(
      CUpti_Profiler_GetCounterAvailability_Params_STRUCT_SIZE);
  avail.ctx = ctx;
  if (!ok(c->cuptiProfilerGetCounterAvailability(&avail), "cuptiProfilerGetCounterAvailability")) return false;
  availability.assign(avail.counterAvailabilityImageSize, 0);
  avail.pCounterAvailabilityImage = availability.data();
  if (!ok(c->cuptiProfilerGetCounterAvailability(&avail), "cuptiProfilerGetCounterAvailability")) return false;
  auto host_init =
      make_params<CUpti_Profiler_Host_Initialize_Params>(CUpti_Profiler_Host_Initialize_Params_STRUCT_SIZE);
  host_init.profilerType = CUPTI_PROFILER_TYPE_RANGE_PROFILER;
  host_init.pChipName = chip.c_str();
  host_init.pCounterAvailabilityImage = availability.data();
  if (!ok(c->cuptiProfilerHostInitialize(&host_init), "cuptiProfilerHostInitialize")) return false;
  host = host_init.pHostObject;
  return configure(unknown);
}

// The metrics this chip knows, and the configuration image that collects them.
bool HwProfiler::Impl::configure(std::string& unknown) {
  for (const std::string& n : hw_metric_names()) {
    auto p = make_params<CUpti_Profiler_Host_GetMetricProperties_Params>(
        CUpti_Profiler_Host_GetMetricProperties_Params_STRUCT_SIZE);
    p.pHostObject = host;
    p.pMetricName = n.c_str();
    if (c->cuptiProfilerHostGetMetricProperties(&p) == CUPTI_SUCCESS)
      names.push_back(n);
    else
      unknown += (unknown.empty() ? "" : ", ") + n;
  }
  for (const std::string& n : names) cnames.push_back(n.c_str());
  if (cnames.empty()) {
    cond.cupti_status = -1;
    cond.cupti_call = "cuptiProfilerHostGetMetricProperties";
    cond.cupti_message = "chip " + chip + " knows none of the metrics";
    return false;
  }
  auto add =
      make_params<CUpti_Profiler_Host_ConfigAddMetrics_Params>(CUpti_Profiler_Host_ConfigAddMetrics_Params_STRUCT_SIZE);
  add.pHostObject = host;
  add.ppMetricNames = cnames.data();
  add.numMetrics = cnames.size();
  if (!ok(c->cuptiProfilerHostConfigAddMetrics(&add), "cuptiProfilerHostConfigAddMetrics")) return false;
  auto size = make_params<CUpti_Profiler_Host_GetConfigImageSize_Params>(
      CUpti_Profiler_Host_GetConfigImageSize_Params_STRUCT_SIZE);
  size.pHostObject = host;
  if (!ok(c->cuptiProfilerHostGetConfigImageSize(&size), "cuptiProfilerHostGetConfigImageSize")) return false;
  config.assign(size.configImageSize, 0);
  auto image =
      make_params<CUpti_Profiler_Host_GetConfigImage_Params>(CUpti_Profiler_Host_GetConfigImage_Params_STRUCT_SIZE);
  image.pHostObject = host;
  image.configImageSize = config.size();
  image.pConfigImage = config.data();
  if (!ok(c->cuptiProfilerHostGetConfigImage(&image), "cuptiProfilerHostGetConfigImage")) return false;
  auto np =
      make_params<CUpti_Profiler_Host_GetNumOfPasses_Params>(CUpti_Profiler_Host_GetNumOfPasses_Params_STRUCT_SIZE);
  np.configImageSize = config.size();
  np.pConfigImage = config.data();
  if (c->cuptiProfilerHostGetNumOfPasses(&np) == CUPTI_SUCCESS) passes = np.numOfPasses;
  return true;
}

// Enables the range profiler, makes a fresh counter-data image, sets the configuration and starts.
bool HwProfiler::Impl::open_session() {
  auto enable = make_params<CUpti_RangeProfiler_Enable_Params>(CUpti_RangeProfiler_Enable_Params_STRUCT_SIZE);
  enable.ctx = ctx;
  if (!ok(c->cuptiRangeProfilerEnable(&enable), "cuptiRangeProfilerEnable")) return false;
  range = enable.pRangeProfilerObject;
  auto size = make_params<CUpti_RangeProfiler_GetCounterDataSize_Params>(
      CUpti_RangeProfiler_GetCounterDataSize_Params_STRUCT_SIZE);
  size.pRangeProfilerObject = range;
  size.pMetricNames = cnames.data();
  size.numMetrics = cnames.size();
  size.maxNumOfRanges = kMaxRanges;
  size.maxNumRangeTreeNodes = kMaxRanges;
  if (!ok(c->cuptiRangeProfilerGetCounterDataSize(&size), "cuptiRangeProfilerGetCounterDataSize")) return false;
  data.assign(size.counterDataSize, 0);
  auto init = make_params<CUpti_RangeProfiler_CounterDataImage_Initialize_Params>(
      CUpti_RangeProfiler_CounterDataImage_Initialize_Params_STRUCT_SIZE);
  init.pRangeProfilerObject = range;
  init.counterDataSize = data.size();
  init.pCounterData = data.data();
  if (!ok(c->cuptiRangeProfilerCounterDataImageInitialize(&init), "cuptiRangeProfilerCounterDataImageInitialize"))
    return false;
  auto set = make_params<CUpti_RangeProfiler_SetConfig_Params>(CUpti_RangeProfiler_SetConfig_Params_STRUCT_SIZE);
  set.pRangeProfilerObject = range;
  set.configSize = config.size();
  set.pConfig = config.data();
  set.counterDataImageSize = data.size();
  set.pCounterDataImage = data.data();
  set.range = CUPTI_AutoRange;
  set.replayMode = CUPTI_KernelReplay;
  set.maxRangesPerPass = kMaxRanges;
  set.numNestingLevels = 1;
  set.minNestingLevel = 1;
  set.passIndex = 0;
  set.targetNestingLevel = 1;
  if (!ok(c->cuptiRangeProfilerSetConfig(&set), "cuptiRangeProfilerSetConfig")) return false;
  auto start = make_params<CUpti_RangeProfiler_Start_Params>(CUpti_RangeProfiler_Start_Params_STRUCT_SIZE);
  start.pRangeProfilerObject = range;
  return ok(c->cuptiRangeProfilerStart(&start), "cuptiRangeProfilerStart");
}

// Stops, decodes and evaluates every range into `ranges`.
bool HwProfiler::Impl::close_session(std::vector<HwRange>& ranges) {
  auto stop = make_params<CUpti_RangeProfiler_Stop_Params>(CUpti_RangeProfiler_Stop_Params_STRUCT_SIZE);
  stop.pRangeProfilerObject = range;
  if (!ok(c->cuptiRangeProfilerStop(&stop), "cuptiRangeProfilerStop")) return false;
  if (!stop.isAllPassSubmitted) {
    cond.cupti_status = -1;
    cond.cupti_call = "cuptiRangeProfilerStop";
    cond.cupti_message = "kernel replay left passes unsubmitted";
    return false;
  }
  auto decode = make_params<CUpti_RangeProfiler_DecodeData_Params>(CUpti_RangeProfiler_DecodeData_Params_STRUCT_SIZE);
  decode.pRangeProfilerObject = range;
  if (!ok(c->cuptiRangeProfilerDecodeData(&decode), "cuptiRangeProfilerDecodeData")) return false;
  auto info = make_params<CUpti_RangeProfiler_GetCounterDataInfo_Params>(
      CUpti_RangeProfiler_GetCounterDataInfo_Params_STRUCT_SIZE);
  info.pCounterDataImage = data.data();
  info.counterDataImageSize = data.size();
  if (!ok(c->cuptiRangeProfilerGetCounterDataInfo(&info), "cuptiRangeProfilerGetCounterDataInfo")) return false;
  std::vector<double> values(cnames.size());
  for (size_t i = 0; i < info.numTotalRanges; ++i) {
    auto name = make_params<CUpti_RangeProfiler_CounterData_GetRangeInfo_Params>(
        CUpti_RangeProfiler_CounterData_GetRangeInfo_Params_STRUCT_SIZE);
    name.pCounterDataImage = data.data();
    name.counterDataImageSize = data.size();
    name.rangeIndex = i;
    name.rangeDelimiter = "/";
    if (!ok(c->cuptiRangeProfilerCounterDataGetRangeInfo(&name), "cuptiRangeProfilerCounterDataGetRangeInfo"))
      return false;
    auto eval = make_params<CUpti_Profiler_Host_EvaluateToGpuValues_Params>(
        CUpti_Profiler_Host_EvaluateToGpuValues_Params_STRUCT_SIZE);
    eval.pHostObject = host;
    eval.pCounterDataImage = data.data();
    eval.counterDataImageSize = data.size();
    eval.rangeIndex = i;
    eval.ppMetricNames = cnames.data();
    eval.numMetrics = cnames.size();
    eval.pMetricValues = values.data();
    if (!ok(c->cuptiProfilerHostEvaluateToGpuValues(&eval), "cuptiProfilerHostEvaluateToGpuValues")) return false;
    HwRange r;
    r.kernel = name.rangeName ? name.rangeName : "";
    for (size_t m = 0; m < names.size(); ++m) r.values[names[m]] = values[m];
    ranges.push_back(std::move(r));
  }
  return true;
}

void HwProfiler::Impl::disable() {
  if (!range) return;
  auto p = make_params<CUpti_RangeProfiler_Disable_Params>(CUpti_RangeProfiler_Disable_Params_STRUCT_SIZE);
  p.pRangeProfilerObject = range;
  c->cuptiRangeProfilerDisable(&p);
  range = nullptr;
}

HwProfiler::HwProfiler() : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.cond.devices = device_count();
#ifdef RAYCOH_CUDA_SIM
  m.cond.simulated = true;
#endif
  m.cond.simulated = m.cond.simulated || device_name().rfind("simulated", 0) == 0;
  if (m.cond.devices > 0 && !m.cond.simulated) m.c = load_cupti(m.cond.library_error);
  if (m.c) m.setup(unknown_);
  unavailable_ = hw_counters_unavailable(m.cond);
  if (!unavailable_.empty()) {
    print_once(unavailable_);
    return;
  }
  print_once("cuda: counters=hw: " + std::to_string(m.names.size()) + " metrics on " + m.chip + " through CUPTI, " +
             std::to_string(m.passes) + " replay pass(es) per kernel" +
             (unknown_.empty() ? "" : "; not on this chip (columns empty): " + unknown_));
}

HwProfiler::~HwProfiler() {
  Impl& m = *impl_;
  if (!m.c) return;
  m.disable();
  if (m.host) {
    auto p = make_params<CUpti_Profiler_Host_Deinitialize_Params>(CUpti_Profiler_Host_Deinitialize_Params_STRUCT_SIZE);
    p.pHostObject = m.host;
    m.c->cuptiProfilerHostDeinitialize(&p);
  }
}

void HwProfiler::begin() {
  Impl& m = *impl_;
  if (!unavailable_.empty() || m.failed) return;
  if (!m.open_session()) {
    m.failed = true;
    m.disable();
    print_once(hw_counters_unavailable(m.cond));
  }
}

std::optional<HwCounters> HwProfiler::end() {
  Impl& m = *impl_;
  if (!unavailable_.empty() || m.failed || !m.range) return std::nullopt;
  std::vector<HwRange> ranges;
  const bool read = m.close_session(ranges);
  m.disable();
  if (!read) {
    m.failed = true;
    print_once(hw_counters_unavailable(m.cond));
    return std::nullopt;
  }
  return combine_ranges(ranges);
}

}  // namespace raycoh::cuda
