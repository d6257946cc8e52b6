#include "records/hw_columns.h"

namespace raycoh {

std::vector<std::string> hw_column_names() {
  std::vector<std::string> names;
  for (const HwMetric& m : hw_metrics()) names.emplace_back(m.column);
  names.emplace_back("hw_pass_dram_bytes_per_ray");
  return names;
}

void append_hw_columns(Schema<ExperimentRow>& s) {
  const std::vector<std::string> names = hw_column_names();
  for (size_t i = 0; i < names.size(); ++i) {
    Column<ExperimentRow> c;
    c.name = names[i];
    c.write = [i](const ExperimentRow& r) {
      return i < r.hw.size() && r.hw[i] ? csv_format::General::write(*r.hw[i]) : std::string();
    };
    c.read = [i, n = names.size()](ExperimentRow& r, const std::string& text) {
      if (text.empty()) return;
      r.hw.resize(n);
      r.hw[i] = csv_format::General::read(text);
    };
    s.push_back(std::move(c));
  }
}

void set_hw_counters(ExperimentRow& row, const HwCounters& c) {
  const std::vector<HwMetric>& metrics = hw_metrics();
  const double rays = static_cast<double>(row.rays);
  row.hw.assign(metrics.size() + 1, std::nullopt);
  if (c.kernels == 0 || rays <= 0) return;
  for (size_t i = 0; i < metrics.size() && i < c.values.size(); ++i) {
    if (!c.values[i]) continue;
    row.hw[i] = metrics[i].kind == HwMetric::Kind::PerRay ? *c.values[i] / rays : *c.values[i];
  }
  row.hw[metrics.size()] = c.pass_dram_bytes / rays;
}

}  // namespace raycoh
