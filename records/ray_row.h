// The record of one `raycoh rays` row (one ray of a batch) and its CSV column table (results/README.md).
#pragma once

#include <cstdint>
#include <string>

#include "core/ray_batch.h"
#include "records/schema.h"
#include "scenes/scene.h"

namespace raycoh {

struct RayRow {
  size_t index = 0;
  uint32_t pixel_x = 0, pixel_y = 0;
  int frame = 0;
  float org_x = 0, org_y = 0, org_z = 0, dir_x = 0, dir_y = 0, dir_z = 0, tmin = 0, tmax = 0;
  float normal_x = 0, normal_y = 0, normal_z = 0;
  std::string material_class;
  float pdf = 0, weight_r = 0, weight_g = 0, weight_b = 0;
  uint32_t tile = 0, group = 0;  // grouping generators only
  std::string group_type;
  std::string key;  // hex, as many digits as the encoder's key has nibbles; encoders with keys only
};

// The columns of a batch: without tile, group and group_type when it has no groups, without key when no encoder
// made keys.
Schema<RayRow> rays_schema(bool groups, bool keys);
// Ray i of the batch (its key is the caller's); width: the image's, for the pixel coordinates.
RayRow ray_row(const RayBatch& batch, size_t i, int width, int frame);

}  // namespace raycoh
