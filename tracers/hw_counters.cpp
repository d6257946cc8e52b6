#include "tracers/hw_counters.h"

#include <algorithm>

namespace raycoh {

const std::vector<HwMetric>& hw_metrics() {
  using K = HwMetric::Kind;
  static const std::vector<HwMetric> metrics = {
      {"hw_l1_hit_pct", K::Percent, {"l1tex__t_sector_hit_rate.pct"}, "L1 sector hit rate"},
      {"hw_l2_hit_pct", K::Percent, {"lts__t_sector_hit_rate.pct"}, "L2 sector hit rate"},
      {"hw_l1_wavefronts_per_ray", K::PerRay, {"l1tex__data_pipe_lsu_wavefronts.sum"}, "L1 data-stage wavefronts"},
      {"hw_l1_tag_wavefronts_per_ray",
       K::PerRay,
       {"l1tex__t_output_wavefronts_pipe_lsu_mem_global_op_ld.sum"},
       "L1 tag-stage wavefronts of global loads"},
      {"hw_l2_bytes_per_ray", K::PerRay, {"lts__t_bytes.sum"}, "L2 bytes"},
      {"hw_dram_bytes_per_ray", K::PerRay, {"dram__bytes_read.sum"}, "DRAM bytes read"},
      {"hw_local_requests_per_ray",
       K::PerRay,
       {"l1tex__t_requests_pipe_lsu_mem_local_op_ld.sum", "l1tex__t_requests_pipe_lsu_mem_local_op_st.sum"},
       "local-memory load and store requests"},
      {"hw_inst_per_ray", K::PerRay, {"smsp__inst_executed.sum"}, "warp instructions"},
      {"hw_issue_pct", K::Percent, {"smsp__issue_active.avg.pct_of_peak_sustained_active"}, "issue-slot utilisation"},
      {"hw_l1_util_pct", K::Percent, {"l1tex__throughput.avg.pct_of_peak_sustained_active"}, "L1 throughput"},
      {"hw_occupancy_pct", K::Percent, {"sm__warps_active.avg.pct_of_peak_sustained_active"}, "achieved occupancy"},
  };
  return metrics;
}

std::vector<std::string> hw_metric_names() {
  std::vector<std::string> names;
  for (const HwMetric& m : hw_metrics())
    for (const char* name : m.metrics)
      if (std::find(names.begin(), names.end(), name) == names.end()) names.emplace_back(name);
  return names;
}

bool is_trace_kernel(const std::string& name) {
  for (const char* k : {"persistent_kernel", "simple_kernel", "fused_noopt_kernel", "fused_group_kernel"})
    if (name.find(k) != std::string::npos) return true;
  return false;
}

namespace {

// A quantity's value in one range: the sum of its metrics, or nothing when one is missing.
std::optional<double> quantity(const HwMetric& m, const HwRange& r) {
  double v = 0;
  for (const char* name : m.metrics) {
    const auto it = r.values.find(name);
    if (it == r.values.end()) return std::nullopt;
    v += it->second;
  }
  return v;
}

}  // namespace

HwCounters combine_ranges(const std::vector<HwRange>& ranges) {
  const std::vector<HwMetric>& metrics = hw_metrics();
  HwCounters h;
  h.values.assign(metrics.size(), std::nullopt);
  std::vector<double> weights(metrics.size(), 0.0);
  for (const HwRange& r : ranges) {
    if (const auto d = r.values.find("dram__bytes_read.sum"); d != r.values.end()) h.pass_dram_bytes += d->second;
    if (!is_trace_kernel(r.kernel)) continue;
    ++h.kernels;
    // Percentages of several kernels are weighted by their instructions (each kernel alone: its own).
    const auto inst = r.values.find("smsp__inst_executed.sum");
    const double w = inst != r.values.end() && inst->second > 0 ? inst->second : 1.0;
    for (size_t i = 0; i < metrics.size(); ++i) {
      const std::optional<double> v = quantity(metrics[i], r);
      if (!v) continue;
      const bool percent = metrics[i].kind == HwMetric::Kind::Percent;
      h.values[i] = h.values[i].value_or(0.0) + (percent ? *v * w : *v);
      if (percent) weights[i] += w;
    }
  }
  for (size_t i = 0; i < metrics.size(); ++i)
    if (h.values[i] && metrics[i].kind == HwMetric::Kind::Percent) *h.values[i] /= weights[i];
  return h;
}

std::string hw_counters_refusal(const std::string& option, const std::string& tracer_params) {
  const std::string text = "," + tracer_params + ",";
  if (text.find(",counters=hw,") == std::string::npos) return "";
  return option +
         ": counters=hw replays every kernel under CUPTI, so its times are no speeds; measure speeds without "
         "it and read the counters with `raycoh table --tracers cuda:counters=hw`";
}

std::string hw_counters_unavailable(const HwCounterConditions& c) {
  std::string why;
  if (c.devices <= 0)
    why = "no CUDA device";
  else if (c.simulated)
    why = "the device is GPGPU-Sim, which has no hardware counters";
  else if (!c.library_error.empty())
    why = "CUPTI cannot be loaded: " + c.library_error;
  else if (c.cupti_status == kCuptiInsufficientPrivileges || c.cupti_status == kCuptiVirtualizedInsufficientPrivileges)
    why = "the driver restricts GPU performance counters to administrators (" + c.cupti_call +
          ": CUPTI_ERROR_INSUFFICIENT_PRIVILEGES; NVreg_RestrictProfilingToAdminUsers=1: run as root or load the "
          "driver with NVreg_RestrictProfilingToAdminUsers=0)";
  else if (c.cupti_status != 0)
    why = c.cupti_call + " failed: CUPTI error " + std::to_string(c.cupti_status) +
          (c.cupti_message.empty() ? "" : " (" + c.cupti_message + ")");
  if (why.empty()) return "";
  return "cuda: counters=hw: hardware counters not available (" + why +
         "); the hw_* columns stay empty and the rows are ordinary timings";
}

}  // namespace raycoh
