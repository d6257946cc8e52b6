// Checked parameter sets and plugin lists.
#include <gtest/gtest.h>

#include "core/error.h"
#include "core/params.h"

namespace raycoh {
namespace {

TEST(Params, DefaultsRangesAndCanonicalForm) {
  ParamSet p("generator 'x'", "k=16,tile=16x8");
  EXPECT_EQ(p.get_int("k", 8, 1, 1024), 16);
  EXPECT_EQ(p.get_size("tile", {8, 8}, 1, 64), std::make_pair(16, 8));
  EXPECT_FLOAT_EQ(p.get_float("lambda", 0.125f, 0.f, 1.f), 0.125f);
  EXPECT_NO_THROW(p.finish());
  EXPECT_EQ(p.canonical(), "k=16,tile=16x8,lambda=0.125");
}

TEST(Params, ErrorsNameTheOwnerAndTheValidChoices) {
  auto message = [](auto fn) {
    try {
      fn();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message([] { ParamSet("tracer 't'", "k=0").get_int("k", 8, 1, 64); }).find("[1, 64]"), std::string::npos);
  EXPECT_NE(message([] { ParamSet("tracer 't'", "k=abc").get_int("k", 8, 1, 64); }).find("tracer 't'"),
            std::string::npos);
  EXPECT_NE(message([] { ParamSet("g", "mode=x").get_choice("mode", "a", {"a", "b"}); }).find("a, b"),
            std::string::npos);
  EXPECT_NE(message([] {
              ParamSet p("g", "zz=1");
              p.get_int("k", 1, 1, 2);
              p.finish();
            }).find("unknown parameter 'zz'; valid parameters: k"),
            std::string::npos);
  EXPECT_THROW(ParamSet("g", "novalue"), Error);
  EXPECT_THROW(ParamSet("g", "k=1,k=2"), Error);
  EXPECT_THROW(parse_size("--res", "64", 1, 100), Error);
  EXPECT_THROW(parse_size("--res", "0x64", 1, 100), Error);
  EXPECT_THROW(parse_size("--res", "64x64x", 1, 100), Error);
  EXPECT_EQ(parse_size("--res", "64x32", 1, 100), std::make_pair(64, 32));
}

TEST(Params, PluginListsKeepParametersWithTheirPlugin) {
  const auto list = split_plugin_list("noopt,ours:tile=8x8,k=16,embree:mode=packet16");
  ASSERT_EQ(list.size(), 3u);
  EXPECT_EQ(list[0].name, "noopt");
  EXPECT_EQ(list[1].name, "ours");
  EXPECT_EQ(list[1].params, "tile=8x8,k=16");
  EXPECT_EQ(list[2].text(), "embree:mode=packet16");
  EXPECT_EQ(split_plugin_list("").size(), 0u);
}

}  // namespace
}  // namespace raycoh
