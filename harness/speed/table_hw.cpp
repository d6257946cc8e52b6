// `raycoh table`'s section for a tracer that read the GPU's own counters (`cuda:counters=hw`, measured through
// CUPTI): per method and scene the trace kernels' hit rates, traffic and instructions per ray and their
// utilisations. Its kernels were replayed by the profiler, so it prints no speed (the rows' run_under says why).
#include <fmt/format.h>

#include <cstdio>

#include "harness/speed/table.h"
#include "records/hw_columns.h"

namespace raycoh {

namespace {

// The value of hw column `name` as text ("—" where the counters could not be read).
std::string hw_cell(const Accumulated& a, const std::string& name, const char* format) {
  const std::vector<std::string> names = hw_column_names();
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) {
      const std::optional<double> v = a.hw.value(i);
      return v ? fmt::format(fmt::runtime(format), *v) : std::string("—");
    }
  return "—";
}

}  // namespace

void print_hw_counters(const std::vector<SceneResult>& results, const std::vector<Method>& methods, const ResultKey& tl,
                       const std::string& name, const std::string& header) {
  std::printf(
      "\n### %s: MEASURED hardware counters of the trace kernels (CUPTI range profiler; kernels replayed, so no "
      "speed): L1 / L2 sector hit %%; per ray: L1 data / tag wavefronts, L2 / DRAM bytes, local requests, warp "
      "instructions; issue / L1 / occupancy %%\n\n%s\n",
      name.c_str(), header.c_str());
  std::vector<std::string> labels = {"primary"};
  for (const Method& m : methods) labels.push_back(m.label);
  for (const std::string& label : labels) {
    std::string line = "| " + (label == "primary" ? std::string("primary (coherent bound)") : label) + " |";
    for (const SceneResult& r : results) {
      const auto& m = r.by_tracer.at(tl);
      const auto it = m.find(label);
      if (it == m.end()) {
        line += " — |";
        continue;
      }
      const Accumulated& a = it->second;
      line +=
          fmt::format(" {} / {}; {} / {}, {} / {} B, {}, {}; {} / {} / {} |", hw_cell(a, "hw_l1_hit_pct", "{:.1f}%"),
                      hw_cell(a, "hw_l2_hit_pct", "{:.1f}%"), hw_cell(a, "hw_l1_wavefronts_per_ray", "{:.1f}"),
                      hw_cell(a, "hw_l1_tag_wavefronts_per_ray", "{:.1f}"), hw_cell(a, "hw_l2_bytes_per_ray", "{:.0f}"),
                      hw_cell(a, "hw_dram_bytes_per_ray", "{:.1f}"), hw_cell(a, "hw_local_requests_per_ray", "{:.2f}"),
                      hw_cell(a, "hw_inst_per_ray", "{:.0f}"), hw_cell(a, "hw_issue_pct", "{:.0f}%"),
                      hw_cell(a, "hw_l1_util_pct", "{:.0f}%"), hw_cell(a, "hw_occupancy_pct", "{:.0f}%"));
    }
    std::printf("%s\n", line.c_str());
  }
}

}  // namespace raycoh
