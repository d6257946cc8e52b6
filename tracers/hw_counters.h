// The GPU's own counters of a trace kernel (`cuda:counters=hw`, read through CUPTI's range profiler in
// cuda/hw_profiler.cpp): what they are, which Nsight Compute metric each one is, and when they cannot be read.
// Plain C++ with no CUDA or CUPTI in it, so that the CPU-only build, the records layer and the tests without a GPU
// see the same table and the same decision.
//
// Measured, never modeled: the values are the hardware's counts and ratios for the kernels of one trace (or one
// device pass), set beside the `simt` model's modeled columns, never added to them. CUPTI replays each kernel once
// per pass its metrics need, so the times of a run that read them are not timings (the row's run_under says
// "cupti-counters", docs/design.md section 4).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace raycoh {

// The value of a row's run_under column (records/provenance.h) when its kernels ran under the range profiler.
inline constexpr const char* kHwCountersRunUnder = "cupti-counters";

// One measured quantity: the Nsight Compute metrics it sums (one or two) and how it is written per row.
struct HwMetric {
  enum class Kind { PerRay, Percent };
  const char* column;  // the CSV column (results/README.md)
  Kind kind;           // PerRay: summed over the trace kernels, divided by the row's rays; Percent: a ratio
  std::vector<const char*> metrics;
  const char* what;
};

// The quantities, in column order: L1 and L2 sector hit rates, L1 data-stage and tag-stage wavefronts, L2 and DRAM
// bytes, local-memory requests, warp instructions, issue-slot and L1 utilisation, achieved occupancy.
const std::vector<HwMetric>& hw_metrics();
// Every distinct metric name of hw_metrics(), in order (what the profiler is configured with).
std::vector<std::string> hw_metric_names();

// The counters of one trace (or device pass): per quantity of hw_metrics(), its value over the trace kernels
// (sums of PerRay metrics, percentages weighted by each kernel's instructions when there are several), empty where
// the chip does not know a metric. kernels: the trace kernels read; pass_dram_bytes: DRAM bytes read by every
// kernel profiled in the pass (generation, keys, sort, gather and trace on a device pipeline).
struct HwCounters {
  std::vector<std::optional<double>> values;  // hw_metrics().size() entries
  int kernels = 0;
  double pass_dram_bytes = 0;
};

// One profiled range: a kernel (its name as CUPTI gives it) and the value of each metric the chip knows.
struct HwRange {
  std::string kernel;
  std::map<std::string, double> values;
};
// The counters of a session's ranges: the trace kernels' (is_trace_kernel) combined as HwCounters says, and every
// range's DRAM bytes in pass_dram_bytes. A quantity stays empty when a metric of it is missing from the ranges.
HwCounters combine_ranges(const std::vector<HwRange>& ranges);

// Whether a profiled kernel (its name as CUPTI gives it, mangled or not) is a trace kernel: the persistent and
// simple kernels of cuda/trace_kernels.cu and the fused kernels of cuda/fused_kernels.cu.
bool is_trace_kernel(const std::string& name);

// Empty when a tracer's parameter text (e.g. "bvh=cwbvh,counters=hw") does not ask for hardware counters; otherwise
// the one line a command that needs speeds (`validate`, `tune`) refuses it with: its kernels would be replayed.
std::string hw_counters_refusal(const std::string& option, const std::string& tracer_params);

// A tracer that reads the GPU's own counters (`cuda` with counters=hw) is also one of these; the harness finds it
// with hw_counter_source(). Kept beside the Tracer interface rather than in it: only the `cuda` tracer has it.
class HwCounterSource {
 public:
  virtual ~HwCounterSource() = default;
  // The counters of the last trace() call or device pass, measured; nullptr where none were read.
  virtual const HwCounters* last_hw_counters() const = 0;
  // What the tracer's measurements run under: "cupti-counters" (kernels replayed by the profiler, so its times are
  // not timings: the rows' run_under column; the harness runs it once per row, like a counting tracer), or "" where
  // CUPTI cannot read counters and the tracer is a plain timing tracer.
  virtual std::string run_under() const = 0;
};

// The tracer's HwCounterSource, or nullptr (every tracer but `cuda:counters=hw`).
template <class T>
const HwCounterSource* hw_counter_source(const T& tracer) {
  return dynamic_cast<const HwCounterSource*>(&tracer);
}
// Its run_under ("" for every other tracer) and last counters (nullptr for every other tracer).
template <class T>
std::string hw_run_under(const T& tracer) {
  const HwCounterSource* s = hw_counter_source(tracer);
  return s ? s->run_under() : std::string();
}
template <class T>
const HwCounters* last_hw_counters(const T& tracer) {
  const HwCounterSource* s = hw_counter_source(tracer);
  return s ? s->last_hw_counters() : nullptr;
}

// What decides whether counters can be read, gathered by cuda/hw_profiler.cpp (or injected by a test).
struct HwCounterConditions {
  int devices = 0;            // CUDA devices
  bool simulated = false;     // the device is GPGPU-Sim (a RAYCOH_CUDA_SIM build)
  std::string library_error;  // why libcupti could not be loaded or lacks an entry point; empty when it loaded
  int cupti_status = 0;       // the first CUPTI call that failed: its CUptiResult (0: none failed)
  std::string cupti_call;     // that call's name
  std::string cupti_message;  // and CUPTI's text for its status
};

// CUptiResult codes the decision names (cupti_result.h).
inline constexpr int kCuptiInsufficientPrivileges = 35, kCuptiVirtualizedInsufficientPrivileges = 40;

// Empty when counters can be read; otherwise the one line that says why not (no device, GPGPU-Sim, libcupti
// missing, profiling restricted to administrators by the driver, another CUPTI failure) and that the counter
// columns stay empty while nothing else of the run changes.
std::string hw_counters_unavailable(const HwCounterConditions& c);

}  // namespace raycoh
