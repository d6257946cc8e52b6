// Checked parameter sets and plugin lists.
#include "core/params.h"

#include <gtest/gtest.h>

#include "core/error.h"

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
  EXPECT_NE(message([] {
              ParamSet("g", "mode=x").get_choice("mode", "a", {"a", "b"});
            }).find("a, b"),
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

const ParamTable& test_table() {
  static const ParamTable table = {
      size_param("tile", {8, 8}, 1, 64, "the tile"),
      int_param("k", 8, 1, 1024, "group size"),
      float_param("lambda", 0.125f, 0.001f, 0.999f, "ratio"),
      choice_param("order", "tile", {"tile", "scanline"}, "batch order"),
      uint_param("seed", 0u, 0u, 0xFFFFFFFFu, "salt"),
  };
  return table;
}

std::string read_all(const std::string& text) {
  ParamSet p("generator 'x'", text, test_table());
  const auto tile = p.get_size("tile");
  p.get_int_at_most("k", tile.first * tile.second);
  p.get_float("lambda");
  p.get_choice("order");
  p.get_uint("seed");
  p.finish();
  return p.canonical();
}

TEST(Params, TableGivesDefaultsRangesAndTheCanonicalForm) {
  EXPECT_EQ(read_all(""), "tile=8x8,k=8,lambda=0.125,order=tile,seed=0");
  EXPECT_EQ(read_all(""), default_params(test_table()));
  EXPECT_EQ(read_all("seed=7,k=16,tile=16x8"), "tile=16x8,k=16,lambda=0.125,order=tile,seed=7");
  auto message = [](const std::string& text) {
    try {
      read_all(text);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // The same messages as reading with explicit defaults and ranges; k's upper end is W H.
  EXPECT_EQ(message("k=65"), "generator 'x': k=65 is not valid; expected an integer in [1, 64]");
  EXPECT_EQ(message("lambda=1"), "generator 'x': lambda=1 is not valid; expected a number in [0.001, 0.999]");
  EXPECT_EQ(message("order=x"), "generator 'x': order=x is not valid; choose one of: tile, scanline");
  EXPECT_EQ(message("zz=1"), "generator 'x': unknown parameter 'zz'; valid parameters: tile, k, lambda, order, seed");
  EXPECT_NE(message("tile=65x1").find("[1, 64]"), std::string::npos);
}

TEST(Params, TableRowsThePluginDoesNotReadOrDeclareAreInternalErrors) {
  ParamSet unread("g", "", test_table());
  unread.get_size("tile");
  EXPECT_THROW(unread.finish(), Error);  // k, lambda, ... declared but never read
  ParamSet undeclared("g", "", test_table());
  EXPECT_THROW(undeclared.get_int("size"), Error);
  EXPECT_THROW(undeclared.get_float("k"), Error);  // declared as an int
}

// A plugin reads each parameter once: a second read would write the key twice into its canonical params(), which a
// row's tracer_params must hold once (a cuda factory reading `counters` twice made every cuda row unreadable).
TEST(Params, ReadingAParameterTwiceIsAnInternalError) {
  ParamSet twice("g", "tile=4x4", test_table());
  twice.get_size("tile");
  try {
    twice.get_size("tile");
    ADD_FAILURE() << "a second read of 'tile' passed";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("reads its parameter 'tile' twice"), std::string::npos) << e.what();
  }
}

TEST(Params, TablesPrintNameTypeDefaultRangeAndDoc) {
  const std::string text = format_param_table(test_table(), "  ");
  EXPECT_NE(text.find("  tile    WxH     8x8    [1, 64] each"), std::string::npos) << text;
  EXPECT_NE(text.find("lambda  float   0.125  [0.001, 0.999]"), std::string::npos) << text;
  EXPECT_NE(text.find("tile | scanline"), std::string::npos) << text;
  EXPECT_EQ(format_param_table({}, "  "), "  (no parameters)\n");
  EXPECT_EQ(param_summary(test_table()).substr(0, 22), "tile=8x8 ([1, 64] each");
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
