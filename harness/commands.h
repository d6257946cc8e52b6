// The smaller subcommands: list, scenes info, rays.
#pragma once

#include <string>

#include "core/params.h"
#include "harness/provenance.h"

namespace raycoh {

void run_list();
void run_scene_info(const std::string& scene_spec);

struct RaysOptions {
  std::string scene;
  PluginSpec generator{"noopt", ""};
  PluginSpec encoder{"none", ""};
  int width = 320, height = 240;
  int frame = 0;
  uint32_t seed = 1;
  std::string out;
};
void run_rays(const RaysOptions& options, const Provenance& provenance);

}  // namespace raycoh
