// Reordering applied two ways gives the same hits: physical permutation + trace, and indirect fetch through the
// sorted indices, for every tracer.
#include <gtest/gtest.h>

#include <cstring>

#include "bvh/bvh_build.h"
#include "encoders/encoder.h"
#include "encoders/reorder.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

TEST(Indirect, SameHitsAsPhysicalPermutationForEveryTracer) {
  const Scene scene = load_scene("voxels:size=32");
  const Bvh bvh = build_bvh(scene);
  const auto order = make_pixel_order(64, 48, RayOrder::Tile, 8, 8);
  const GBuffer gbuffer = first_hits(scene, *make_tracer({"cpu", ""}, scene, bvh), 64, 48, order, 1, 0).gbuffer;
  RayBatch batch, sorted;
  GenerationStats stats;
  make_generator({"noopt", ""})->generate(scene, gbuffer, 1, batch, stats);
  ASSERT_GT(batch.size(), 100u);

  for (const char* enc : {"origin", "twopoint", "mlhcc"}) {
    auto encoder = make_encoder({enc, ""}, EncoderContext{scene.bounds, &bvh});
    std::vector<uint32_t> perm;
    ReorderTimings t;
    ASSERT_TRUE(reorder(*encoder, batch, PermuteMode::Physical, sorted, perm, t));
    for (const char* tr : {"cpu", "embree", "embree:mode=packet16", "embree:mode=stream_coherent"}) {
      auto tracer = make_tracer(parse_plugin_spec(tr), scene, bvh);
      std::vector<Hit> physical(batch.size()), indirect(batch.size());
      tracer->trace(sorted.rays.data(), sorted.size(), physical.data());
      tracer->trace_indirect(batch.rays.data(), perm.data(), batch.size(), indirect.data());
      EXPECT_EQ(std::memcmp(physical.data(), indirect.data(), physical.size() * sizeof(Hit)), 0) << enc << " " << tr;
    }
  }
}

}  // namespace
}  // namespace raycoh
