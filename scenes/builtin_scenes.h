// The registry of built-in procedural scenes (scenes/procedural.cpp), in the shape of every plugin registry
// (core/plugin.h), so that `raycoh list` prints their parameters like the other plugins'.
#pragma once

#include <vector>

#include "core/plugin.h"
#include "scenes/scene.h"

namespace raycoh {

// Reads its values from a ParamSet over the record's table; throws raycoh::Error for bad ones.
using SceneFactory = Scene (*)(ParamSet& params);
using SceneInfo = PluginInfo<SceneFactory>;

const std::vector<SceneInfo>& builtin_scene_infos();

}  // namespace raycoh
