// What a result is keyed by: the tracer that measured it, as typed fields (docs/design.md section 1). Rows give
// it (result_key in records/experiment_row.h), the console tables, the report and the sweep look results up by it
// and name them with label(): the one rule a tracer is named by in tables, figures and columns.
// scripts/result_key.py is the same rule in Python.
#pragma once

#include <map>
#include <string>
#include <tuple>
#include <vector>

namespace raycoh {

struct ResultKey {
  std::string tracer;  // the registry name: cpu, embree, cuda, simt
  std::string preset;  // simt's GPU preset, empty for other tracers (records/recorded_columns.h)
  std::string mode;    // embree's call mode, empty for other tracers
  std::string layout;  // the tracer's acceleration structure (Tracer::bvh_layout, the bvh column)
  std::string params;  // every parameter, canonical (the tracer_params column): tells apart what the rest does not

  // "simt[preset=h100]", "embree[mode=packet16]", "cpu": the name and what tells tracers of one name apart in a
  // figure; with every_parameter, "simt[preset=h100,l1_tags=4,...]" (the name alone without parameters).
  std::string label(bool every_parameter = false) const;

  auto tie() const { return std::tie(tracer, preset, mode, layout, params); }
  bool operator<(const ResultKey& o) const { return tie() < o.tie(); }
  bool operator==(const ResultKey& o) const { return tie() == o.tie(); }
  bool operator!=(const ResultKey& o) const { return !(*this == o); }
};

// The names of a set of results' tracers in headings: label(), or the label with every parameter where two of
// them would share the short one.
std::map<ResultKey, std::string> heading_labels(const std::vector<ResultKey>& keys);

}  // namespace raycoh
