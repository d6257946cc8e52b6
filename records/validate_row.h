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
  std::string table;        // table1 | table3 | bound (primary rays, not in the paper)
  std::string row;          // our method label
  std::string paper_scene;  // the paper's column (Table 1: Breakfast ... Vokselia; Table 3: Sibenik)
  std::string paper_row;
  std::string tile;
  int k = 0;
  double paper_mray_s = NAN, paper_ratio = NAN;
  // What our figure is: "modeled" (simt), "measured" (a GPU) or "simulated" (GPGPU-Sim); a modeled figure is in the
  // modeled columns, the others in the measured ones, never both.
  std::string kind = "modeled";
  double modeled_mray_s = NAN, modeled_ratio = NAN;
  // Measured: the trace's MRay/s (median of the repeats), its ratio to noopt and the ratio's paired 95% interval
  // (records/speed_interval.h), and whether the paper's ratio lies inside that interval ("yes", "no"; "" without
  // an interval).
  double measured_mray_s = NAN, measured_ratio = NAN, ratio_lo = NAN, ratio_hi = NAN;
  std::string paper_in_interval;
  double ratio_error = NAN;  // our ratio / the paper's - 1
  std::string limiter;
  std::string scene, preset, tracer_params, order;
  int width = 0, height = 0;
  Provenance provenance;
};

const Schema<ValidateRow>& validate_schema();

}  // namespace raycoh
