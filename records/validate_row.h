// The record of one `raycoh validate` row (one compared cell of the paper's Tables 1 and 3) and its CSV column
// table (results/README.md).
#pragma once

#include <cmath>
#include <string>

#include "records/provenance.h"
#include "records/schema.h"

namespace raycoh {

// One compared cell: a row of the comparison CSV.
struct ValidateRow {
  std::string table;  // table1 | table3 | bound (primary rays, not in the paper)
  std::string row;    // our method label
  std::string paper_row;
  std::string tile;
  int k = 0;
  double paper_mray_s = NAN, paper_ratio = NAN;
  double modeled_mray_s = 0, modeled_ratio = 0, ratio_error = NAN;  // (modeled - paper) / paper
  std::string limiter;
  std::string scene, preset, tracer_params, order;
  int width = 0, height = 0;
  Provenance provenance;
};

const Schema<ValidateRow>& validate_schema();

}  // namespace raycoh
