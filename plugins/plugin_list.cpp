// Lives in plugins/ because it reads every registry: generators/, encoders/, scenes/ and plugins/tracer_registry.h.
#include "plugins/plugin_list.h"

#include "encoders/encoder.h"
#include "generators/generator.h"
#include "plugins/tracer_registry.h"
#include "scenes/builtin_scenes.h"

namespace raycoh {

std::string plugin_list_text() {
  return "Generators (--generators name[:key=value,...]):\n" + format_plugins(generator_infos()) +
         "\nEncoders (--encoders name[:key=value,...]; key encoders also record box=lo..hi, the scene bounds "
         "positions are quantised in):\n" +
         format_plugins(encoder_infos()) + "\nTracers (--tracers name[:key=value,...]):\n" +
         format_plugins(tracer_infos()) +
         "\nBuilt-in scenes (--scenes name[:key=value,...], or any .gltf/.glb/.obj path or folder):\n" +
         format_plugins(builtin_scene_infos());
}

}  // namespace raycoh
