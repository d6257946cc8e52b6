// Every registry record's parameter table is what its plugin reads: made with no parameters, each plugin's
// canonical set is the table's defaults in table order; unknown keys name the table's rows; `list` shows them.
#include <gtest/gtest.h>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "encoders/encoder.h"
#include "generators/generator.h"
#include "plugins/plugin_list.h"
#include "plugins/tracer_registry.h"
#include "scenes/builtin_scenes.h"
#include "scenes/scene.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

std::string error_of(auto fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

// The old generator name `tile` stands for `contiguous` in one rule (generator_name), and whether a generator groups
// pixels is asked of its parameter table (a group size k), never of its name.
TEST(PluginSchema, TheTileAliasAndGroupingAreAskedOfTheRegistry) {
  EXPECT_EQ(generator_name("tile"), "contiguous");
  EXPECT_EQ(generator_name("ours"), "ours");
  EXPECT_EQ(make_generator(parse_plugin_spec("tile:k=4"))->params(),
            make_generator(parse_plugin_spec("contiguous:k=4"))->params());
  for (const char* g : {"ours", "contiguous", "tile"}) {
    const ParamSpec* k = group_size_row(g);
    ASSERT_NE(k, nullptr) << g;
    EXPECT_EQ(k->name, "k");
    EXPECT_GE(k->hi, 64) << g;
  }
  for (const char* g : {"noopt", "direct", "sadeghi", "microjitter", "nonesuch"})
    EXPECT_EQ(group_size_row(g), nullptr) << g;
}

TEST(PluginSchema, GeneratorsReadTheirTables) {
  for (const GeneratorInfo& info : generator_infos()) {
    SCOPED_TRACE(info.name);
    EXPECT_EQ(make_generator({info.name, ""})->params(), default_params(info.table()));
    EXPECT_NE(error_of([&] {
                make_generator({info.name, "bogus=1"});
              })
                  .find("valid parameters: " +
                        [&] {
                          std::vector<std::string> names;
                          for (const ParamSpec& s : info.table()) names.push_back(s.name);
                          return join(names);
                        }()),
              std::string::npos);
  }
}

TEST(PluginSchema, EncodersReadTheirTablesThenRecordTheBox) {
  const Scene scene = load_scene("cornell");
  const Bvh bvh = build_bvh(scene);
  const EncoderContext context{scene.bounds, &bvh};
  for (const EncoderInfo& info : encoder_infos()) {
    SCOPED_TRACE(info.name);
    const std::string params = make_encoder({info.name, ""}, context)->params();
    EXPECT_EQ(params.substr(0, params.find(",box=")), info.name == "none" ? "" : default_params(info.table()));
    EXPECT_NE(error_of([&] {
                make_encoder({info.name, "bogus=1"}, context);
              }).find("unknown parameter 'bogus'"),
              std::string::npos);
  }
}

TEST(PluginSchema, TracersAndScenesReadTheirTables) {
  const Scene scene = load_scene("cornell");
  const Bvh bvh = build_bvh(scene);
  for (const TracerInfo& info : tracer_infos()) {
    SCOPED_TRACE(info.name);
    // simt's table is the registry's transitional copy until simt/ reads through one; cuda needs a device.
    if (info.name == "simt" || info.name == "cuda") continue;
    EXPECT_EQ(make_tracer({info.name, ""}, scene, bvh)->params(), default_params(info.table()));
  }
  EXPECT_NE(error_of([&] {
              make_tracer({"embree", "mode=x"}, scene, bvh);
            }).find("single, packet16"),
            std::string::npos);
  EXPECT_NO_THROW(load_scene("voxels:size=8"));
  EXPECT_NE(error_of([] { load_scene("voxels:size=2"); }).find("[4, 1024]"), std::string::npos);
  EXPECT_NE(error_of([] { load_scene("voxels:bogus=2"); }).find("valid parameters: size"), std::string::npos);
}

TEST(PluginSchema, ListShowsEveryPluginWithItsTable) {
  const std::string text = plugin_list_text();
  for (const auto& info : generator_infos()) EXPECT_NE(text.find("  " + info.name + " "), std::string::npos);
  for (const auto& info : encoder_infos()) EXPECT_NE(text.find("  " + info.name + " "), std::string::npos);
  for (const auto& info : tracer_infos()) EXPECT_NE(text.find("  " + info.name + " "), std::string::npos);
  for (const auto& info : builtin_scene_infos()) EXPECT_NE(text.find("  " + info.name + " "), std::string::npos);
  EXPECT_NE(text.find("order   choice  tile   tile | group | scanline"), std::string::npos) << text;
  EXPECT_NE(text.find("size  int  64  [4, 1024]  columns"), std::string::npos) << text;
}

}  // namespace
}  // namespace raycoh
