// Fuzz target of plugin specs and their parameter strings: the --generators, --encoders and --tracers lists of
// every command (core/params.cpp split_plugin_list, ParamSet, and each registry's make_<kind>).
#include <memory>
#include <string>

#include "bvh/bvh_build.h"
#include "core/params.h"
#include "encoders/encoder.h"
#include "generators/generator.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "tests/fuzz/fuzz_targets.h"
#include "tests/fuzz/fuzz_util.h"

namespace raycoh::fuzz {

namespace {

// The scene tracers and encoders are made for (32 triangles, built once).
}  // namespace

// First byte: which list (generators, encoders, tracers); the rest: the list as typed after the option.
void fuzz_plugin_params(const uint8_t* data, size_t size) {
  if (size < 1) return;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (text.find('\0') != std::string::npos) return;  // a command-line argument cannot hold one
  const int kind = data[0] % 3;
  std::vector<PluginSpec> specs;
  expect_clean("", [&] { specs = split_plugin_list(text); });
  for (const PluginSpec& spec : specs) {
    const SmallScene& s = small_scene();
    // `tile` is the old name of the contiguous generator: a warning says so, and errors name `contiguous`.
    const std::string shown = kind == 0 && spec.name == "tile" ? "contiguous" : spec.name;
    expect_clean("'" + shown + "'", [&] {
      if (kind == 0) {
        make_generator(spec);
      } else if (kind == 1) {
        make_encoder(spec, EncoderContext{s.scene.bounds, &s.bvh});
      } else {
        make_tracer(spec, s.scene, s.bvh);
      }
    });
  }
}

}  // namespace raycoh::fuzz
