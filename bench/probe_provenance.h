// The provenance columns of the CUDA probes' CSVs (bench/stage_bounds.cu, bench/l1_probe.cu), like every other
// raycoh CSV's (records/provenance.h: revision, build, machine, device, what the run was wrapped in, and the GPU's
// SMs, driver, runtime and clocks at start and end). Plain strings, so that .cu files (which cannot include fmt
// under nvcc 13) can write them; implemented in probe_provenance.cpp.
#pragma once

#include <string>

namespace raycoh {

// ",git_revision,...": the column names, each after a comma, to end a CSV header line.
std::string probe_provenance_header();

// Reads the run's provenance and the GPU's facts and start clocks (call before measuring).
void probe_provenance_start(int argc, char** argv);

// ",<value>,...": the values for one row (clocks at the start and now), each CSV-escaped after a comma.
std::string probe_provenance_values();

}  // namespace raycoh
