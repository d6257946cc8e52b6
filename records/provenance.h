// Where a result came from: code revision, build, machine, library versions, run settings, command line.
// Every CSV row carries these columns so rows stay interpretable after files are merged.
#pragma once

#include <string>

#include "core/params.h"
#include "records/schema.h"

namespace raycoh {

struct Provenance {
  std::string git_revision;
  std::string build_type;
  std::string compiler;
  std::string cpu;     // model name and logical core count
  std::string host;    // the machine's host name (rows of merged shards say where each was measured)
  std::string device;  // "cpu", or the CUDA device's name on rows a cuda tracer measured (device_of)
  std::string embree_version;
  int threads = 0;        // worker threads in use
  std::string timestamp;  // UTC, ISO 8601, when the run started
  std::string command_line;
};

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
