// `raycoh render`: one generator's image of one scene, on the CPU or the device path tracer (render.cpp;
// --device is common.device, render_options.h).
#pragma once

#include <string>
#include <vector>

#include "core/params.h"
#include "harness/image/render_options.h"
#include "records/provenance.h"

namespace raycoh {

// `raycoh render --scene S --generator G --frames N --out img.exr [--crop x,y,w,h]...`
struct RenderOptions {
  RenderCommon common;
  std::string scene = "cornell";
  PluginSpec generator{"noopt", ""};
  int frames = 32;                 // --frames [1, 1 << 20]
  std::string out = "render.exr";  // .exr (float), .png (tone-mapped 8-bit) or .pfm
  std::vector<Crop> crops;         // each written as <out stem>-crop<i><out extension>
};
int run_render(const RenderOptions& options, const Provenance& provenance);

}  // namespace raycoh
