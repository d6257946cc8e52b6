// The windowed reordering stage `window` (encoders/window.cpp): its order is a permutation that keeps every ray
// inside its window of W, sorts each window by bin stably, equals `none` (identity) at W = 1 and a global stable
// sort by bin when one window holds the batch; bad parameters are one-line errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <vector>

#include "encoders/encoder.h"
#include "encoders/reorder.h"
#include "tests/encoder_test_util.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

using test::box_of;
using test::make_batch;
using test::random_rays;
using test::tiny_bvh;

std::vector<uint32_t> order_of(const std::string& spec, const EncoderContext& ctx, const RayBatch& batch) {
  auto encoder = make_encoder(parse_plugin_spec(spec), ctx);
  RayBatch out;
  std::vector<uint32_t> order;
  ReorderTimings t;
  EXPECT_TRUE(reorder(*encoder, batch, PermuteMode::Physical, out, order, t)) << spec;
  for (size_t i = 0; i < order.size(); ++i) EXPECT_EQ(out.rays[i].org.x, batch.rays[order[i]].org.x);
  return order;
}

uint32_t octant(const Ray& r) { return (r.dir.x < 0.f) | (r.dir.y < 0.f) << 1 | (r.dir.z < 0.f) << 2; }

TEST(Window, IsAWindowLocalStablePermutation) {
  const Bounds box = box_of({-1, -1, -1}, {1, 1, 1});
  const Bvh bvh = tiny_bvh();
  const EncoderContext ctx{box, &bvh};
  const RayBatch batch = make_batch(random_rays(box, 5000, 3));
  for (const char* spec : {"window:W=64,key=octant", "window:W=1000,key=origin,bits=4", "window:W=333,key=twopoint",
                           "window:W=4096,key=mlhcc,bits=12", "window:W=7,key=reis,bits=1"}) {
    SCOPED_TRACE(spec);
    const std::vector<uint32_t> order = order_of(spec, ctx, batch);
    ASSERT_EQ(order.size(), batch.size());
    std::vector<uint32_t> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    for (uint32_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i);
    const int w = parse_plugin_spec(spec).params.find("W=64") != std::string::npos ? 64 : 0;
    const std::vector<uint64_t> keys = test::keys_of(spec, ctx, batch);
    for (size_t i = 0; i < order.size(); ++i) {
      // The window index sits above at most 16 bin bits: keys >> 16 is the window, or a group of windows.
      const uint64_t window = keys[order[i]] >> 16;
      EXPECT_EQ(keys[order[i]] >> 16, keys[i] >> 16) << "position " << i << " left its window";
      if (i > 0 && keys[order[i - 1]] >> 16 == window) {
        EXPECT_LE(keys[order[i - 1]], keys[order[i]]) << i;  // binned
        if (keys[order[i - 1]] == keys[order[i]]) {
          EXPECT_LT(order[i - 1], order[i]) << i;  // stable
        }
      }
      if (w == 64) {
        EXPECT_EQ(order[i] / 64, i / 64);
      }
    }
  }
  // Octant bins: inside a window the octants come in ascending order.
  const std::vector<uint32_t> o = order_of("window:W=64,key=octant", ctx, batch);
  for (size_t i = 1; i < o.size(); ++i)
    if (i % 64 != 0) {
      EXPECT_LE(octant(batch.rays[o[i - 1]]), octant(batch.rays[o[i]])) << i;
    }
}

TEST(Window, WindowOfOneIsNone) {
  const Bounds box = box_of({-1, -1, -1}, {1, 1, 1});
  const EncoderContext ctx{box, nullptr};
  const RayBatch batch = make_batch(random_rays(box, 3001, 5));
  for (const char* spec : {"window:W=1", "window:W=1,key=octant", "window:W=1,key=costa,bits=16"}) {
    const std::vector<uint32_t> order = order_of(spec, ctx, batch);
    for (uint32_t i = 0; i < order.size(); ++i) ASSERT_EQ(order[i], i) << spec;
  }
}

TEST(Window, OneWindowIsAGlobalStableSortByBin) {
  const Bounds box = box_of({-1, -1, -1}, {1, 1, 1});
  const EncoderContext ctx{box, nullptr};
  const RayBatch batch = make_batch(random_rays(box, 2000, 8));
  const std::vector<uint32_t> order = order_of("window:W=16777216,key=octant", ctx, batch);
  std::vector<uint32_t> expect(batch.size());
  std::iota(expect.begin(), expect.end(), 0u);
  std::stable_sort(expect.begin(), expect.end(),
                   [&](uint32_t a, uint32_t b) { return octant(batch.rays[a]) < octant(batch.rays[b]); });
  EXPECT_EQ(order, expect);
}

TEST(Window, Errors) {
  const EncoderContext ctx{box_of({0, 0, 0}, {1, 1, 1}), nullptr};
  for (const char* spec : {"window:W=0", "window:bits=17", "window:key=morton", "window:w=4"}) {
    const std::string msg = test::error_of([&] { make_encoder(parse_plugin_spec(spec), ctx); });
    EXPECT_NE(msg.find("encoder 'window'"), std::string::npos) << spec << ": " << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
  // mlhcc needs the BVH.
  EXPECT_NE(test::error_of([&] { make_encoder(parse_plugin_spec("window:key=mlhcc"), ctx); }), "no error");
  // Too many windows for the key's bits beside 16 bin bits.
  const RayBatch batch = make_batch(test::random_rays(box_of({0, 0, 0}, {1, 1, 1}), 70000, 1));
  auto e = make_encoder(parse_plugin_spec("window:W=1,bits=16"), ctx);
  std::vector<uint64_t> keys(batch.size());
  EXPECT_NE(test::error_of([&] { e->encode(batch, keys.data()); }).find("windows"), std::string::npos);
}

}  // namespace
}  // namespace raycoh
