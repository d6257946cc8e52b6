// The record of one `raycoh stability` row (one scene x batch x case) and its CSV column table (results/README.md).
#pragma once

#include <cstdint>
#include <string>

#include "records/provenance.h"
#include "records/schema.h"

namespace raycoh {

struct StabilityRow {
  std::string scene, spec;
  size_t triangles = 0;
  std::string batch, name;
  size_t count = 0, of = 0;
  double rate = 0, threshold = 0;  // threshold NaN (empty) when reported only
  std::string status;              // ok | FAIL | reported
  int width = 0, height = 0, frame = 0;
  uint32_t seed = 0;
  size_t max_rays = 0;
  Provenance provenance;
};

const Schema<StabilityRow>& stability_schema();

}  // namespace raycoh
