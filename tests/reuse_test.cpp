// The paper's generator (`ours`) and its ablations (`tile`, `direct`): grouping structure, the per-pixel
// cosine distribution (goodness of fit with a fixed seed), shared tangent-space directions, and the stiff and
// extreme cases of docs/design.md section 7. G-buffers are built by hand so every case is exactly what it says.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <set>

#include "core/error.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "generators/generator.h"
#include "generators/tiles.h"

namespace raycoh {
namespace {

// One diffuse (0), one glossy (1), one specular (2), one transmissive (3) material.
Scene material_scene(float glossy_roughness = 0.3f) {
  Scene s;
  s.name = "materials";
  Material d;
  d.cls = MaterialClass::Diffuse;
  Material g;
  g.cls = MaterialClass::Glossy;
  g.roughness = glossy_roughness;
  g.metallic = 1.f;
  Material sp = g;
  sp.cls = MaterialClass::Specular;
  sp.roughness = 0.f;
  Material t;
  t.cls = MaterialClass::Transmissive;
  t.transmission = 1.f;
  s.materials = {d, g, sp, t};
  return s;
}

// A w x h G-buffer of points on the plane z = 0 looking straight down, all with material `material`.
GBuffer flat_gbuffer(const Scene& scene, int w, int h, uint32_t frame, uint32_t material = 0) {
  GBuffer g;
  g.width = w;
  g.height = h;
  g.frame = frame;
  g.points.resize(static_cast<size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      ShadingPoint& p = g.points[static_cast<size_t>(y) * w + x];
      p.position = {static_cast<float>(x), static_cast<float>(y), 0.f};
      p.ng = p.ns = {0.f, 0.f, 1.f};
      p.wo = normalize(Vec3{0.1f, 0.2f, 1.f});
      p.prim = static_cast<uint32_t>(y * w + x);
      p.material = material;
      p.cls = scene.materials[material].cls;
    }
  g.hits = g.points.size();
  return g;
}

RayBatch run(const std::string& spec, const Scene& scene, const GBuffer& g, uint32_t seed = 1,
             GenerationStats* stats = nullptr) {
  RayBatch b;
  GenerationStats s;
  make_generator(parse_plugin_spec(spec))->generate(scene, g, seed, b, s);
  if (stats) *stats = s;
  return b;
}

bool all_finite(const RayBatch& b) {
  for (size_t i = 0; i < b.size(); ++i)
    if (!is_finite(b.rays[i].org) || !is_finite(b.rays[i].dir) || !std::isfinite(b.pdf[i]) || !is_finite(b.weight[i]))
      return false;
  return true;
}

TEST(TileShuffle, IsAFullPeriodBijectionForAnyTileSize) {
  for (uint32_t m : {1u, 2u, 3u, 5u, 7u, 12u, 64u, 100u, 128u, 255u, 256u, 1000u}) {
    for (uint32_t tile = 0; tile < 5; ++tile) {
      const TileShuffle s = make_tile_shuffle(m, 7, 3, tile);
      std::vector<int> seen(m, 0);
      for (uint32_t i = 0; i < m; ++i) {
        const uint32_t v = s(i);
        ASSERT_LT(v, m);
        ++seen[v];
      }
      for (uint32_t i = 0; i < m; ++i) ASSERT_EQ(seen[i], 1) << "m " << m;
      // Full period: iterating the shuffle from 0 visits every number before returning.
      uint32_t x = 0, steps = 0;
      do {
        x = s(x);
        ++steps;
      } while (x != 0 && steps <= m);
      EXPECT_EQ(steps, m) << "m " << m;
    }
  }
}

TEST(Ours, EveryPixelOfAFullTileIsInExactlyOneGroupOfK) {
  const Scene scene = material_scene();
  for (int k : {1, 4, 8, 16, 64}) {
    const GBuffer g = flat_gbuffer(scene, 32, 16, 0);
    const RayBatch b = run("ours:tile=8x8,k=" + std::to_string(k), scene, g);
    ASSERT_EQ(b.size(), 32u * 16u);
    std::set<uint32_t> pixels(b.pixel.begin(), b.pixel.end());
    EXPECT_EQ(pixels.size(), b.size());
    std::map<uint32_t, int> group_size;
    std::map<uint32_t, uint32_t> tile_of_group;
    for (size_t i = 0; i < b.size(); ++i) {
      ++group_size[b.group[i]];
      const uint32_t x = b.pixel[i] % 32, y = b.pixel[i] / 32;
      EXPECT_EQ(b.tile[i], (y / 8) * 4 + x / 8);
      if (tile_of_group.count(b.group[i])) {
        EXPECT_EQ(tile_of_group[b.group[i]], b.tile[i]);
      }
      tile_of_group[b.group[i]] = b.tile[i];
    }
    EXPECT_EQ(group_size.size(), 8u * 64 / k);
    for (const auto& [id, n] : group_size) EXPECT_EQ(n, k) << "k " << k;
  }
}

// Members of group q of tile t, as sets of in-tile pixel numbers, for comparing groupings.
std::set<std::set<uint32_t>> groups_of_tile(const RayBatch& b, uint32_t tile, int width) {
  std::map<uint32_t, std::set<uint32_t>> by_group;
  for (size_t i = 0; i < b.size(); ++i)
    if (b.tile[i] == tile) by_group[b.group[i]].insert((b.pixel[i] / width % 8) * 8 + b.pixel[i] % width % 8);
  std::set<std::set<uint32_t>> out;
  for (auto& [id, s] : by_group) out.insert(s);
  return out;
}

TEST(Ours, GroupingChangesBetweenTilesAndFramesButNotForTheAblation) {
  const Scene scene = material_scene();
  const RayBatch f0 = run("ours", scene, flat_gbuffer(scene, 16, 8, 0));
  const RayBatch f1 = run("ours", scene, flat_gbuffer(scene, 16, 8, 1));
  EXPECT_NE(groups_of_tile(f0, 0, 16), groups_of_tile(f0, 1, 16));  // between tiles
  EXPECT_NE(groups_of_tile(f0, 0, 16), groups_of_tile(f1, 0, 16));  // between frames
  // Interleaved: a group is spread over the tile, not a run of 8 consecutive pixel numbers.
  int contiguous = 0;
  for (const auto& grp : groups_of_tile(f0, 0, 16)) contiguous += *grp.rbegin() - *grp.begin() == 7;
  EXPECT_LT(contiguous, 8);
  const RayBatch t0 = run("contiguous", scene, flat_gbuffer(scene, 16, 8, 0));
  const RayBatch t1 = run("contiguous", scene, flat_gbuffer(scene, 16, 8, 1));
  EXPECT_EQ(groups_of_tile(t0, 0, 16), groups_of_tile(t1, 0, 16));
  for (const auto& grp : groups_of_tile(t0, 0, 16)) EXPECT_EQ(*grp.rbegin() - *grp.begin(), 7u);
}

TEST(Ours, KEqualsOneIsNoOptBitForBit) {
  const Scene scene = material_scene();
  GBuffer g = flat_gbuffer(scene, 24, 16, 3);
  for (size_t i = 0; i < g.points.size(); ++i) {  // mixed materials and normals
    g.points[i].material = static_cast<uint32_t>(i % 4);
    g.points[i].cls = scene.materials[g.points[i].material].cls;
    g.points[i].ns = g.points[i].ng = normalize(Vec3{std::sin(0.1f * i), std::cos(0.3f * i), 1.5f});
  }
  const RayBatch a = run("ours:k=1", scene, g, 5);
  const RayBatch b = run("noopt", scene, g, 5);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.pixel, b.pixel);
  EXPECT_EQ(std::memcmp(a.rays.data(), b.rays.data(), a.size() * sizeof(Ray)), 0);
  EXPECT_EQ(std::memcmp(a.pdf.data(), b.pdf.data(), a.size() * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(a.weight.data(), b.weight.data(), a.size() * sizeof(Vec3)), 0);
}

// Pearson chi-square of counts against equal expected frequencies.
double chi2_uniform(const std::vector<int>& counts) {
  double total = 0;
  for (int c : counts) total += c;
  const double e = total / counts.size();
  double chi2 = 0;
  for (int c : counts) chi2 += (c - e) * (c - e) / e;
  return chi2;
}

// Over many frames, the direction each diffuse pixel uses is cosine-distributed around its own normal: under
// that distribution u = cos^2(theta) and v = phi / 2pi are independent and uniform, so a 4 x 4 grid over (u, v)
// has equal expected counts. Each pixel has its own tilted normal, so sharing a tangent-space direction between
// differently oriented pixels is exercised. 64 pixels x 3200 frames; fixed seed, so the outcome is fixed.
TEST(Ours, EachDiffusePixelIsCosineDistributedAroundItsOwnNormal) {
  const Scene scene = material_scene();
  GBuffer g = flat_gbuffer(scene, 8, 8, 0);
  for (size_t i = 0; i < g.points.size(); ++i)
    g.points[i].ns = g.points[i].ng = normalize(Vec3{0.6f * std::sin(1.7f * i), 0.6f * std::cos(2.3f * i), 1.f});
  const int frames = 3200, bins = 4;
  std::vector<std::vector<int>> per_pixel(64, std::vector<int>(bins * bins, 0));
  auto generator = make_generator({"ours", ""});
  RayBatch b;
  GenerationStats st;
  for (int f = 0; f < frames; ++f) {
    g.frame = static_cast<uint32_t>(f);
    generator->generate(scene, g, 42, b, st);
    for (size_t i = 0; i < b.size(); ++i) {
      const Vec3 local = make_frame(g.points[b.pixel[i]].ns).to_local(b.rays[i].dir);
      ASSERT_GT(local.z, 0.f);
      const double u = local.z * local.z, v = (std::atan2(local.y, local.x) + kPi) / (2 * kPi);
      const int bu = std::min(bins - 1, static_cast<int>(u * bins)),
                bv = std::min(bins - 1, static_cast<int>(v * bins));
      ++per_pixel[b.pixel[i]][bu * bins + bv];
    }
  }
  // 15 degrees of freedom per pixel: 1e-4 upper quantile 47.0 (64 pixels, so 0.0064 expected false alarms).
  for (int p = 0; p < 64; ++p) EXPECT_LT(chi2_uniform(per_pixel[p]), 47.0) << "pixel " << p;
  // (Pooling pixels would be wrong: within a frame the members of a group share one direction, so pooled
  // samples are not independent. Across frames each pixel's samples are.)
}

TEST(Ours, DiffuseGroupMembersShareTheTangentSpaceDirection) {
  const Scene scene = material_scene();
  GBuffer g = flat_gbuffer(scene, 16, 16, 2);
  for (size_t i = 0; i < g.points.size(); ++i)
    g.points[i].ns = g.points[i].ng = normalize(Vec3{0.5f * std::sin(0.7f * i), 0.5f * std::cos(1.3f * i), 1.f});
  GenerationStats stats;
  const RayBatch b = run("ours", scene, g, 9, &stats);
  EXPECT_EQ(stats.groups[static_cast<int>(GroupType::Diffuse)], 4u * 8u);
  std::map<uint32_t, Vec3> local_of_group;
  for (size_t i = 0; i < b.size(); ++i) {
    ASSERT_EQ(b.group_type[i], GroupType::Diffuse);
    const Vec3 local = make_frame(g.points[b.pixel[i]].ns).to_local(b.rays[i].dir);
    auto [it, fresh] = local_of_group.emplace(b.group[i], local);
    if (!fresh) {
      EXPECT_LT(length(it->second - local), 1e-5f);
    }
  }
  // Coplanar members get identical world directions.
  const GBuffer flat = flat_gbuffer(scene, 8, 8, 0);
  const RayBatch f = run("ours", scene, flat, 9);
  std::map<uint32_t, Vec3> dir_of_group;
  for (size_t i = 0; i < f.size(); ++i) {
    auto [it, fresh] = dir_of_group.emplace(f.group[i], f.rays[i].dir);
    if (!fresh) {
      EXPECT_EQ(std::memcmp(&it->second, &f.rays[i].dir, sizeof(Vec3)), 0);
    }
  }
}

TEST(Ours, HybridGroupsGiveDiffuseMembersTheGlossyMean) {
  const Scene scene = material_scene(0.2f);
  GBuffer g = flat_gbuffer(scene, 2, 2, 0);
  g.points[0].material = g.points[1].material = 1;  // two glossy, two diffuse, all in one group (K = 4)
  g.points[0].cls = g.points[1].cls = MaterialClass::Glossy;
  GenerationStats stats;
  const RayBatch b = run("ours:tile=2x2,k=4", scene, g, 3, &stats);
  EXPECT_EQ(stats.groups[static_cast<int>(GroupType::Hybrid)], 1u);
  EXPECT_EQ(stats.hybrid_mean_fallback, 0u);
  Vec3 mean{0, 0, 0};
  for (size_t i = 0; i < b.size(); ++i)
    if (b.material[i] == MaterialClass::Glossy) mean += b.rays[i].dir;  // one plane: local = world
  mean = normalize(mean);
  for (size_t i = 0; i < b.size(); ++i) {
    if (b.material[i] != MaterialClass::Diffuse) continue;
    EXPECT_LT(length(b.rays[i].dir - mean), 1e-5f);
    EXPECT_NEAR(b.pdf[i], mean.z / kPi, 1e-5f);  // the member's own Lambert pdf at that direction
  }
}

TEST(Ours, NearlyCancellingGlossyMeanFallsBackToADiffuseDonor) {
  const Scene scene = material_scene(0.f);  // near-mirror glossy
  GBuffer g = flat_gbuffer(scene, 2, 2, 0);
  const float c = 0.004f, s = std::sqrt(1.f - c * c);  // grazing views, 89.77 degrees
  g.points[0].material = g.points[1].material = 1;
  g.points[0].cls = g.points[1].cls = MaterialClass::Glossy;
  g.points[0].wo = {s, 0.f, c};  // mirror reflections point in opposite tangent directions
  g.points[1].wo = {-s, 0.f, c};
  GenerationStats stats;
  const RayBatch b = run("ours:tile=2x2,k=4", scene, g, 3, &stats);
  EXPECT_EQ(stats.hybrid_mean_fallback, 1u);
  EXPECT_TRUE(all_finite(b));
  for (size_t i = 0; i < b.size(); ++i)
    if (b.material[i] == MaterialClass::Diffuse) {
      EXPECT_GT(b.rays[i].dir.z, 0.f);
    }
}

TEST(Ours, ReusedDirectionBelowTheGeometricSurfaceIsKeptWithZeroWeight) {
  const Scene scene = material_scene();
  GBuffer g = flat_gbuffer(scene, 8, 8, 0);
  for (ShadingPoint& p : g.points) p.ns = normalize(Vec3{0.95f, 0.f, 0.05f});  // shading normal nearly in-plane
  GenerationStats stats;
  const RayBatch b = run("ours", scene, g, 1, &stats);
  EXPECT_GT(stats.below_geometric, 0u);
  size_t zero = 0;
  for (size_t i = 0; i < b.size(); ++i)
    if (b.rays[i].dir.z <= 0.f) {
      EXPECT_EQ(b.weight[i].x, 0.f);
      ++zero;
    }
  EXPECT_EQ(zero, stats.below_geometric);
  EXPECT_TRUE(all_finite(b));
}

TEST(Ours, ExtremeSizesGiveOneRayPerHitPixel) {
  const Scene scene = material_scene();
  struct Case {
    int w, h;
    std::string spec;
    size_t groups;  // expected groups with hits
  };
  const std::vector<Case> cases = {
      {1, 1, "ours", 1},                     // 1x1 image
      {5, 3, "ours", 2},                     // tile larger than the image: one 5x3 tile, 15 pixels, K = 8
      {13, 9, "ours:tile=4x4,k=16", 12},     // K = W H; image not a multiple of the tile
      {12, 12, "ours:tile=4x4,k=3", 9 * 6},  // K does not divide W H: groups of 3,3,3,3,3,1
      {16, 16, "ours:tile=8x8,k=64", 4},
  };
  for (const Case& c : cases) {
    GenerationStats stats;
    const RayBatch b = run(c.spec, scene, flat_gbuffer(scene, c.w, c.h, 1), 1, &stats);
    EXPECT_EQ(b.size(), static_cast<size_t>(c.w * c.h)) << c.spec;
    std::set<uint32_t> px(b.pixel.begin(), b.pixel.end());
    EXPECT_EQ(px.size(), b.size()) << c.spec;
    EXPECT_EQ(stats.groups[static_cast<int>(GroupType::Diffuse)], c.groups) << c.spec << " " << c.w << "x" << c.h;
    EXPECT_TRUE(all_finite(b));
  }
  EXPECT_THROW(make_generator({"ours", "k=65"}), Error);
  EXPECT_THROW(make_generator({"ours", "tile=0x8"}), Error);
  EXPECT_THROW(make_generator({"ours", "tile=1024x1024"}), Error);
  EXPECT_THROW(make_generator({"ours", "order=zigzag"}), Error);
}

TEST(Ours, GroupOrderPutsWholeGroupsTogether) {
  const Scene scene = material_scene();
  const RayBatch b = run("ours:order=group", scene, flat_gbuffer(scene, 16, 16, 4));
  for (size_t i = 0; i < b.size(); i += 8)
    for (size_t j = i; j < i + 8; ++j) EXPECT_EQ(b.group[j], b.group[i]);
}

TEST(Ours, MissingPixelsEmitNoRayAndNeverShiftTheGrouping) {
  const Scene scene = material_scene();
  GBuffer g = flat_gbuffer(scene, 8, 8, 0);
  const RayBatch full = run("ours", scene, g);
  for (size_t i = 0; i < g.points.size(); i += 3) g.points[i].prim = kNoHit;
  g.hits = 0;
  for (const ShadingPoint& p : g.points) g.hits += p.valid();
  const RayBatch part = run("ours", scene, g);
  EXPECT_EQ(part.size(), g.hits);
  std::map<uint32_t, uint32_t> group_of_pixel;
  for (size_t i = 0; i < full.size(); ++i) group_of_pixel[full.pixel[i]] = full.group[i];
  for (size_t i = 0; i < part.size(); ++i) EXPECT_EQ(part.group[i], group_of_pixel[part.pixel[i]]);
}

// No NaN or Inf leaves a generator, whatever the G-buffer holds: poles, grazing views, roughness 0 and 1,
// shading normals opposite to the geometric one, and NaN/Inf positions and normals.
TEST(Generators, NoNonFiniteRayEverLeaves) {
  for (float rough : {0.f, 1e-6f, 1.f}) {
    const Scene scene = material_scene(rough);
    GBuffer g = flat_gbuffer(scene, 16, 8, 7);
    const float nan = std::nanf(""), inf = __builtin_huge_valf();
    const std::vector<Vec3> normals = {
        {0, 0, 1},   {0, 0, -1}, normalize(Vec3{1e-7f, 0, -1}), normalize(Vec3{0, 1e-7f, 1}), {1, 0, 0}, {nan, 0, 1},
        {inf, 0, 0}, {0, 0, 0}};
    for (size_t i = 0; i < g.points.size(); ++i) {
      ShadingPoint& p = g.points[i];
      p.material = static_cast<uint32_t>(i % 4);
      p.cls = scene.materials[p.material].cls;
      p.ns = normals[i % normals.size()];
      p.ng = normals[(i / 3) % normals.size()];
      p.wo = i % 5 == 0 ? Vec3{1, 0, 1e-8f} : normalize(Vec3{0.3f, 0.1f, 1.f});  // grazing views too
      if (i % 11 == 0) p.position = {nan, 0, 0};
      if (i % 13 == 0) p.position = {inf, 1e30f, -1e30f};
    }
    size_t flagged = 0;
    for (const char* spec : {"noopt", "ours", "ours:k=1", "ours:k=64", "contiguous", "direct"}) {
      GenerationStats stats;
      const RayBatch b = run(spec, scene, g, 1, &stats);
      EXPECT_EQ(b.size(), g.points.size()) << spec;
      EXPECT_TRUE(all_finite(b)) << spec << " roughness " << rough;
      flagged += stats.non_finite;
    }
    EXPECT_GT(flagged, 0u);
  }
}

TEST(Direct, SharesOneWorldDirectionPerTileAndCountsBackFacingUse) {
  const Scene scene = material_scene();
  GBuffer g = flat_gbuffer(scene, 16, 16, 0);
  for (size_t i = 0; i < g.points.size();
       ++i)  // half the pixels face another way: the shared direction can be behind them
    if (i % 2) g.points[i].ns = g.points[i].ng = normalize(Vec3{0.f, 1.f, 0.1f});
  GenerationStats stats;
  const RayBatch b = run("direct", scene, g, 2, &stats);
  std::map<uint32_t, Vec3> dir_of_tile;
  for (size_t i = 0; i < b.size(); ++i) {
    auto [it, fresh] = dir_of_tile.emplace(b.tile[i], b.rays[i].dir);
    if (!fresh) {
      EXPECT_EQ(std::memcmp(&it->second, &b.rays[i].dir, sizeof(Vec3)), 0);
    }
  }
  EXPECT_EQ(stats.groups[static_cast<int>(GroupType::WorldShared)], 4u);
  EXPECT_GT(stats.below_shading + stats.below_geometric, 0u);
}

}  // namespace
}  // namespace raycoh
