// The shared host/device steps of the grouping (generators/grouping.h, grouping_block.h, core/tile_grid.h) on the
// CPU. The CUDA block phases are run here thread by thread on the host and must give the CPU tile loop's batch bit
// for bit, so a change to either formulation is caught without a GPU (the gpu tests then pin the device).
#include <gtest/gtest.h>

#include <cstring>

#include "bvh/bvh_build.h"
#include "core/rng.h"
#include "core/tile_grid.h"
#include "generators/grouping_block.h"
#include "generators/pixel_order.h"
#include "generators/tangent_reuse.h"
#include "generators/tiles.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

TEST(Grouping, DonorRankIsDefinedForEveryDiffuseCount) {
  GroupingConfig c;
  c.group_seed = 123;
  c.frame = 4;
  // No or one diffuse member: nothing to draw. The GPU asks for every group, all-glossy ones too (n = 0); a rule
  // written `n == 1 ? 0 : rng % n` divides by zero there, which is how the two copies once drifted apart.
  EXPECT_EQ(donor_rank(c, 17, 0), 0u);
  EXPECT_EQ(donor_rank(c, 17, 1), 0u);
  for (uint32_t n = 2; n < 70; ++n) {
    EXPECT_LT(donor_rank(c, n, n), n);
    EXPECT_EQ(donor_rank(c, n, n), rng_u32(c.group_seed, c.frame, n, kDimGroupDonor) % n);
  }
}

TEST(Grouping, CensusClassifiesByVotingMembers) {
  auto type_of = [](std::initializer_list<MaterialClass> members) {
    GroupCensus census;
    for (MaterialClass m : members) census.add(m);
    return census.type();
  };
  using M = MaterialClass;
  EXPECT_EQ(type_of({M::Diffuse, M::Emissive}), GroupType::Diffuse);
  EXPECT_EQ(type_of({M::Glossy, M::Specular}), GroupType::Glossy);
  EXPECT_EQ(type_of({M::Glossy, M::Diffuse, M::Transmissive}), GroupType::Hybrid);
  EXPECT_EQ(type_of({M::Transmissive}), GroupType::Independent);
  EXPECT_EQ(type_of({M::Transmissive, M::Diffuse}), GroupType::Diffuse);
}

TEST(Grouping, DonorSearchTakesTheRankedDiffuseMember) {
  using M = MaterialClass;
  DonorSearch donor{1};
  const M members[] = {M::Glossy, M::Diffuse, M::Transmissive, M::Emissive, M::Diffuse};
  for (uint32_t j = 0; j < 5; ++j) donor.offer(members[j], 100 + j);
  EXPECT_TRUE(donor.found);
  EXPECT_EQ(donor.pixel, 103u);  // the second diffuse-like member
}

TEST(TileGridShared, TileMajorSlotInvertsThePixelOrder) {
  for (auto [w, h, tw, th] : {std::array<int, 4>{64, 48, 8, 8},
                              {250, 190, 16, 8},
                              {13, 9, 4, 4},
                              {7, 5, 32, 32},
                              {1, 1, 8, 8},
                              {31, 17, 5, 3}}) {
    const std::vector<uint32_t> order = make_pixel_order(w, h, RayOrder::Tile, tw, th);
    const TileGrid grid(w, h, tw, th);
    for (size_t slot = 0; slot < order.size(); ++slot)
      ASSERT_EQ(grid.tile_major_slot(static_cast<int>(order[slot] % w), static_cast<int>(order[slot] / w)), slot)
          << w << "x" << h << " tile " << tw << "x" << th;
  }
}

// The CUDA group kernel's phases, thread by thread (cuda/device_grouping.cu does the same with barriers).
RayBatch block_batch(const Scene& scene, const GBuffer& g, const GroupingConfig& c, int tw, int th,
                     GenerationStats& stats) {
  const TileGrid grid(g.width, g.height, tw, th);
  const std::vector<uint32_t> offsets = tile_hit_offsets(g, grid), slots = scanline_slots(g);
  std::vector<BsdfParams> materials;
  for (const Material& m : scene.materials) materials.push_back(bsdf_params(m));
  RayBatch out;
  out.resize(g.hits, true);
  const BatchView view = batch_view(out);
  const auto full_m = static_cast<uint32_t>(tw * th);
  const uint32_t groups = (full_m + c.k - 1) / c.k;
  std::vector<uint32_t> shared(tile_groups_bytes(full_m, groups, c.k) / 4 + 1);
  const TileGroups sh = carve_tile_groups(reinterpret_cast<unsigned char*>(shared.data()), full_m, groups, c.k);
  stats = GenerationStats{};
  for (uint32_t t = 0; t < static_cast<uint32_t>(grid.count()); ++t) {
    const TileBlock b = make_tile_block(c, grid, t, g.points.data(), materials.data(), sh);
    std::vector<uint32_t> rank(b.m), hit(b.m);
    uint32_t hits = 0;
    for (uint32_t i = 0; i < b.m; ++i) {
      hit[i] = phase_assign(b, i);
      rank[i] = hits;
      hits += hit[i];
    }
    if (hits == 0) continue;
    for (uint32_t i = 0; i < b.m; ++i)
      if (hit[i]) phase_member_rank(b, i);
    for (uint32_t q = 0; q < b.groups; ++q) {
      const GroupCensus census = phase_census(b, q);
      if (census.count > 0) ++stats.groups[static_cast<int>(census.type())];
    }
    phase_starts(b);
    for (uint32_t q = 0; q < b.groups; ++q)
      if (sh.count[q] > 0) phase_positions(b, q);
    for (uint32_t i = 0; i < b.m; ++i)
      if (hit[i] && !is_diffuse_like(sh.cls[i]))
        tally_ray(phase_own_lobe(b, view, i, pixel_slot(b, i, rank[i], offsets.data(), slots.data())), stats);
    for (uint32_t q = 0; q < b.groups; ++q) {
      if (sh.count[q] == 0 || sh.diffuse[q] == 0) continue;
      const SharedDirection d = phase_shared_direction(b, q);
      stats.hybrid_mean_fallback += d.hybrid_fallback;
      stats.reused_rays += reused_members(c, static_cast<GroupType>(sh.type[q]), d, sh.diffuse[q]);
    }
    for (uint32_t i = 0; i < b.m; ++i)
      if (hit[i] && is_diffuse_like(sh.cls[i]))
        tally_ray(phase_reuse(b, view, i, pixel_slot(b, i, rank[i], offsets.data(), slots.data())), stats);
  }
  return out;
}

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

TEST(GroupingBlock, HostRunOfTheBlockPhasesEqualsTheCpuGeneratorBitForBit) {
  const Scene scene = load_scene("cornell");
  const Bvh bvh = build_bvh(scene);
  auto tracer = make_tracer({"cpu", ""}, scene, bvh);
  struct Case {
    const char* spec;
    int tw, th;
  };
  for (uint32_t frame : {0u, 3u}) {
    const GBuffer g =
        first_hits(scene, *tracer, 97, 61, make_pixel_order(97, 61, RayOrder::Tile, 8, 8), 1, frame).gbuffer;
    for (const Case& k : {Case{"ours", 8, 8}, Case{"ours:k=1", 8, 8}, Case{"ours:tile=16x8,k=5,order=group", 16, 8},
                          Case{"ours:order=scanline,k=3,seed=9", 8, 8}, Case{"ours:tile=32x32,k=64", 32, 32},
                          Case{"contiguous", 8, 8}, Case{"contiguous:tile=3x5,k=4,order=group", 3, 5},
                          Case{"ours:hybrid=donor", 8, 8}, Case{"ours:hybrid=glossy,frame=rotate", 8, 8},
                          Case{"ours:hybrid=independent,k=16", 8, 8}, Case{"ours:frame=rotate,k=32", 8, 8}}) {
      SCOPED_TRACE(std::string(k.spec) + " frame " + std::to_string(frame));
      auto gen = make_generator(parse_plugin_spec(k.spec));
      RayBatch cpu;
      GenerationStats cs, bs;
      gen->generate(scene, g, 7, cpu, cs);
      const auto& reuse = dynamic_cast<const TangentSpaceReuse&>(*gen);
      const RayBatch block = block_batch(scene, g, reuse.config(7, g.frame), k.tw, k.th, bs);
      EXPECT_TRUE(same_bytes(block.rays, cpu.rays));
      EXPECT_TRUE(same_bytes(block.pixel, cpu.pixel));
      EXPECT_TRUE(same_bytes(block.pdf, cpu.pdf));
      EXPECT_TRUE(same_bytes(block.weight, cpu.weight));
      EXPECT_TRUE(same_bytes(block.normal, cpu.normal));
      EXPECT_TRUE(same_bytes(block.material, cpu.material));
      EXPECT_TRUE(same_bytes(block.tile, cpu.tile));
      EXPECT_TRUE(same_bytes(block.group, cpu.group));
      EXPECT_TRUE(same_bytes(block.group_type, cpu.group_type));
      EXPECT_EQ(bs.rays, cs.rays);
      EXPECT_EQ(bs.below_geometric, cs.below_geometric);
      EXPECT_EQ(bs.below_shading, cs.below_shading);
      for (int t = 0; t < 5; ++t) EXPECT_EQ(bs.groups[t], cs.groups[t]) << "groups of type " << t;
      EXPECT_EQ(bs.hybrid_mean_fallback, cs.hybrid_mean_fallback);
      EXPECT_EQ(bs.reused_rays, cs.reused_rays);
    }
  }
}

TEST(Contiguous, OldNameTileRunsContiguous) {
  EXPECT_EQ(make_generator({"tile", "k=4"})->params(), make_generator({"contiguous", "k=4"})->params());
}

}  // namespace
}  // namespace raycoh
