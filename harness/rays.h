// `raycoh rays`: one frame's secondary ray batch as CSV, one row per ray (schema in results/README.md).
#pragma once

#include <string>

#include "core/params.h"
#include "records/provenance.h"

namespace raycoh {

struct RaysOptions {
  std::string scene;
  PluginSpec generator{"noopt", ""};
  PluginSpec encoder{"none", ""};  // its key is written per ray (hex) when it makes one
  int width = 320, height = 240;   // --res, each in [1, 16384]
  int frame = 0;                   // --frame [0, 2^30]
  uint32_t seed = 1;
  std::string out;     // required
  bool force = false;  // --force: replace an existing --out
};
int run_rays(const RaysOptions& options, const Provenance& provenance);

}  // namespace raycoh
