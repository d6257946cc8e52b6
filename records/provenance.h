// Where a result came from: code revision, build, machine, library versions, run settings, command line.
// Every CSV row carries these columns so rows stay interpretable after files are merged.
#pragma once

#include <optional>
#include <string>

#include "core/params.h"
#include "records/schema.h"

namespace raycoh {

struct Provenance {
  std::string git_revision;
  std::string build_type;
  std::string compiler;
  std::string cpu;      // model name and logical core count
  std::string host;     // the machine's host name (rows of merged shards say where each was measured)
  std::string machine;  // host name and a hash of the machine id, CPU and memory: tells apart hosts of one name
  std::string device;   // "cpu", or the CUDA device's name on rows a cuda tracer measured (device_of)
  std::string embree_version;
  int threads = 0;        // worker threads in use
  std::string timestamp;  // UTC, ISO 8601, when the run started
  std::string command_line;
  // What the run was wrapped in, when not run alone: "ncu", "nsys", "compute-sanitizer" (RAYCOH_RUN_UNDER, or the
  // injection library CUDA_INJECTION64_PATH names), "" otherwise. Its times are not timings: the report, the
  // summaries and validate never read them as speeds.
  std::string run_under;
};

// The GPU of a row a GPU measured (empty on every other row): SMs, the driver's and CUDA runtime's versions, and
// device 0's SM and memory clocks when the row's measurement started and when it ended (MHz, NVML).
struct GpuProvenance {
  std::optional<int> sms;
  std::string driver, runtime;
  std::optional<int> sm_mhz_start, sm_mhz_end, mem_mhz_start, mem_mhz_end;
};

// The facts of `tracer`'s device (no clocks); empty for a tracer on the CPU.
GpuProvenance gpu_provenance(const PluginSpec& tracer);
// Reads the current clocks into the start or end fields (nothing without NVML or a GPU).
void read_gpu_clocks(GpuProvenance& g, bool start);
// The columns of GpuProvenance, documented in results/README.md.
const Schema<GpuProvenance>& gpu_provenance_schema();

Provenance collect_provenance(int argc, char** argv, int threads);

// The device a tracer runs on, for the `device` column: the CUDA device's name for `cuda`, else "cpu".
std::string device_of(const PluginSpec& tracer);
// Whether that device is simulated (a RAYCOH_CUDA_SIM build under GPGPU-Sim, docs/gpgpusim.md): its figures are
// labelled SIMULATED, never measured.
bool simulated_device(const PluginSpec& tracer);

// The provenance columns every CSV ends with; git_revision, build_type, cpu and threads (everything a timing
// depends on besides the row's own settings) are part of the resume key.
const Schema<Provenance>& provenance_schema();

}  // namespace raycoh
