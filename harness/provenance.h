// Where a result came from: code revision, build, machine, library versions, run settings, command line.
// Every CSV row carries these columns so rows stay interpretable after files are merged.
#pragma once

#include <string>
#include <vector>

namespace raycoh {

struct Provenance {
  std::string git_revision;
  std::string build_type;
  std::string compiler;
  std::string cpu;       // model name and logical core count
  std::string device;    // "cpu only" or the GPU's name
  std::string embree_version;
  int threads = 0;       // worker threads in use
  std::string timestamp; // UTC, ISO 8601, when the run started
  std::string command_line;
};

Provenance collect_provenance(int argc, char** argv, int threads);

// Column names and values, in a fixed order.
std::vector<std::string> provenance_columns();
std::vector<std::string> provenance_values(const Provenance& p);

}  // namespace raycoh
