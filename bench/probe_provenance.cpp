#include "bench/probe_provenance.h"

#include "records/csv.h"
#include "records/provenance.h"

namespace raycoh {
namespace {

struct ProbeProvenance {
  Provenance run;
  GpuProvenance gpu;
};

ProbeProvenance& state() {
  static ProbeProvenance s;
  return s;
}

}  // namespace

std::string probe_provenance_header() {
  std::string h;
  for (const auto& c : gpu_provenance_schema()) h += "," + c.name;
  for (const auto& c : provenance_schema()) h += "," + c.name;
  return h;
}

void probe_provenance_start(int argc, char** argv) {
  ProbeProvenance& s = state();
  s.run = collect_provenance(argc, argv, 1);
  s.run.device = device_of(PluginSpec{"cuda", ""});
  s.gpu = gpu_provenance(PluginSpec{"cuda", ""});
  read_gpu_clocks(s.gpu, true);
}

std::string probe_provenance_values() {
  ProbeProvenance& s = state();
  GpuProvenance gpu = s.gpu;
  read_gpu_clocks(gpu, false);
  std::string v;
  for (const auto& c : gpu_provenance_schema()) v += "," + csv_escape(c.write(gpu));
  for (const auto& c : provenance_schema()) v += "," + csv_escape(c.write(s.run));
  return v;
}

}  // namespace raycoh
