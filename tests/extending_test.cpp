// The worked examples of docs/extending.md: a toy generator, a toy encoder and a toy tracer, each written the way
// a plugin file of generators/, encoders/ and tracers/ is (doc block, parameter table, factory), made through a
// PluginInfo record exactly as the registries make theirs, and run on the built-in cornell box. The registries
// are static tables (generators/registry.cpp, encoders/registry.cpp, plugins/tracer_registry.cpp) that a test
// cannot add to, so the records live in test-local lists here; a real plugin puts the same record in the
// registry's table. Also: every GPU preset of the `simt` model and every experiment CSV column passes the checks
// a new one must pass.
#include <gtest/gtest.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <fstream>
#include <numeric>
#include <set>
#include <sstream>

#include "bvh/bvh_build.h"
#include "core/traverse.h"
#include "encoders/key_encoder.h"
#include "encoders/reorder.h"
#include "generators/emit_per_pixel.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "records/experiment_row.h"
#include "simt/gpu_model.h"

namespace raycoh {
namespace {

// --- A generator: generators/<name>.cpp ---------------------------------------------------------------------
// Toy "normal" generator: every hit pixel sends its ray along the shading normal, on the camera's side.
// Parameters: order (choice scanline | tile, default tile): the batch order, tiles of 8x8.
const ParamTable& toy_normal_params() {
  static const ParamTable table = {
      choice_param("order", "tile", {"scanline", "tile"}, "batch order: image rows, or 8x8 tiles")};
  return table;
}

class ToyNormalGenerator final : public Generator {
 public:
  explicit ToyNormalGenerator(RayOrder order) : order_(order) {}
  void generate(const Scene&, const GBuffer& gbuffer, uint32_t, RayBatch& out, GenerationStats& stats) override {
    emit_per_valid_pixel(gbuffer, order_, {8, 8}, out, stats,
                         [](int, int, uint32_t, const ShadingPoint& sp, GenerationStats&) {
                           const Vec3 n = dot(sp.ns, sp.wo) < 0.f ? -sp.ns : sp.ns;
                           return DirectionSample{n, 1.f, {1.f, 1.f, 1.f}, kSampleOk};
                         });
  }
  std::string params() const override { return order_ == RayOrder::Tile ? "order=tile" : "order=scanline"; }

 private:
  RayOrder order_;
};

std::unique_ptr<Generator> make_toy_normal_generator(ParamSet& params) {
  const RayOrder order = parse_ray_order(params.get_choice("order"));
  params.finish();
  return std::make_unique<ToyNormalGenerator>(order);
}

// --- An encoder: encoders/<name>.cpp -------------------------------------------------------------------------
// Toy "octant" encoder: the key is the octant of the ray's direction (sign bits of x, y, z) in the code's top
// three bits, so a sort groups rays by octant. Parameters: bits (the shared key_bits_param(): 32 | 64).
const ParamTable& toy_octant_params() {
  static const ParamTable table = {key_bits_param()};
  return table;
}

uint64_t octant_of(const Vec3& d) { return (d.x < 0.f ? 4u : 0u) | (d.y < 0.f ? 2u : 0u) | (d.z < 0.f ? 1u : 0u); }

std::unique_ptr<Encoder> make_toy_octant_encoder(ParamSet& params, const EncoderContext& context) {
  KeyRecipe recipe;  // kind None: no device version, so cuda:pipeline=device refuses it by name
  recipe.bits = read_key_bits(params);
  recipe.box = context.bounds;
  return make_key_encoder("toy_octant", recipe, finish_encoder_params(params, context.bounds),
                          [](const Ray& r) { return octant_of(r.dir) << 61; });
}

// --- A tracer: tracers/<name>.cpp ----------------------------------------------------------------------------
// Toy "brute" tracer: every ray against every triangle with the watertight test of core/traverse.h, no BVH.
// Parameters: none.
const ParamTable& toy_brute_params() {
  static const ParamTable table;
  return table;
}

class ToyBruteTracer final : public Tracer {
 public:
  explicit ToyBruteTracer(const Bvh& bvh) : bvh_(bvh) {}
  void trace(const Ray* rays, size_t count, Hit* hits) override {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        const PreparedRay p = prepare_ray(rays[i]);
        hits[i] = Hit{};
        hits[i].t = rays[i].tmax;
        for (const BvhTriangle& tri : bvh_.tris) intersect_triangle(p, tri, hits[i]);
        if (!hits[i].valid()) hits[i] = Hit{};
      }
    });
  }
  std::string params() const override { return ""; }  // trace_indirect: the base class gathers, then traces

 private:
  const Bvh& bvh_;
};

std::unique_ptr<Tracer> make_toy_brute_tracer(ParamSet& params, const Scene&, const Bvh& bvh) {
  params.finish();
  return std::make_unique<ToyBruteTracer>(bvh);
}

// --- The records: what a real plugin adds to its registry's table --------------------------------------------
const std::vector<GeneratorInfo>& toy_generators() {
  static const std::vector<GeneratorInfo> infos = {{"toy_normal", "example: every pixel's ray along its shading normal",
                                                    toy_normal_params, make_toy_normal_generator}};
  return infos;
}
const std::vector<EncoderInfo>& toy_encoders() {
  static const std::vector<EncoderInfo> infos = {
      {"toy_octant", "example: the direction's octant", toy_octant_params, make_toy_octant_encoder}};
  return infos;
}
const std::vector<TracerInfo>& toy_tracers() {
  static const std::vector<TracerInfo> infos = {
      {"toy_brute", "example: every triangle for every ray", toy_brute_params, make_toy_brute_tracer}};
  return infos;
}

// make_generator / make_encoder / make_tracer, over a test-local list: find the record, read its parameters.
template <class Info, class... Args>
auto make_from(const std::vector<Info>& infos, const std::string& kind, const std::string& text, Args&&... args) {
  const PluginSpec spec = parse_plugin_spec(text);
  const Info& info = find_plugin(infos, kind, spec.name);
  ParamSet params(kind + " '" + spec.name + "'", spec.params, info.table());
  return info.make(params, std::forward<Args>(args)...);
}

struct Cornell {
  Scene scene = load_scene("cornell");
  Bvh bvh = build_bvh(scene);
  GBuffer gbuffer;
  Cornell() {
    const int w = 48, h = 32;
    const auto order = make_pixel_order(w, h, RayOrder::Tile, 8, 8);
    gbuffer = first_hits(scene, *make_tracer({"cpu", ""}, scene, bvh), w, h, order, 1, 0).gbuffer;
  }
  RayBatch toy_batch(const std::string& spec, GenerationStats& stats) const {
    RayBatch batch;
    make_from(toy_generators(), "generator", spec)->generate(scene, gbuffer, 1, batch, stats);
    return batch;
  }
};

std::vector<Hit> trace_all(Tracer& tracer, const RayBatch& batch, const std::vector<uint32_t>* order = nullptr) {
  std::vector<Hit> hits(batch.size());
  if (order)
    tracer.trace_indirect(batch.rays.data(), order->data(), order->size(), hits.data());
  else
    tracer.trace(batch.rays.data(), batch.size(), hits.data());
  return hits;
}

TEST(Extending, RecordsReadTheirParameterTables) {
  EXPECT_EQ(make_from(toy_generators(), "generator", "toy_normal")->params(), "order=tile");
  EXPECT_EQ(make_from(toy_generators(), "generator", "toy_normal:order=scanline")->params(), "order=scanline");
  EXPECT_THROW(make_from(toy_generators(), "generator", "toy_normal:order=zigzag"), Error);
  EXPECT_THROW(make_from(toy_generators(), "generator", "toy_normal:k=3"), Error);  // unknown keys are errors
  const EncoderContext ctx{Bounds{{0, 0, 0}, {1, 1, 1}}, nullptr};
  EXPECT_EQ(make_from(toy_encoders(), "encoder", "toy_octant:bits=64", ctx)->key_bits(), 64);
  EXPECT_NE(format_plugins(toy_encoders()).find("toy_octant"), std::string::npos);  // what `raycoh list` prints
}

// The generator: one ray per hit pixel, each leaving on the camera's side, and none hits the triangle it leaves.
TEST(Extending, ToyGeneratorEmitsOneEscapingRayPerHitPixel) {
  const Cornell c;
  GenerationStats stats;
  const RayBatch batch = c.toy_batch("toy_normal", stats);
  size_t hit_pixels = 0;
  for (const ShadingPoint& sp : c.gbuffer.points) hit_pixels += sp.valid();
  ASSERT_GT(hit_pixels, 0u);
  EXPECT_EQ(batch.size(), hit_pixels);
  EXPECT_EQ(stats.rays, hit_pixels);
  EXPECT_EQ(stats.below_geometric, 0u);
  const std::vector<Hit> hits = trace_all(*make_tracer({"cpu", ""}, c.scene, c.bvh), batch);
  size_t hits_elsewhere = 0;
  for (size_t i = 0; i < batch.size(); ++i) {
    const ShadingPoint& sp = c.gbuffer.points[batch.pixel[i]];
    EXPECT_GT(dot(batch.rays[i].dir, sp.ng) * dot(sp.wo, sp.ng), 0.f) << "ray " << i;
    EXPECT_NE(hits[i].prim, sp.prim) << "ray " << i << " hits the triangle it leaves";
    hits_elsewhere += hits[i].valid();
  }
  EXPECT_GT(hits_elsewhere, batch.size() / 2);  // the box is closed but for its front: most rays hit a wall
}

// The encoder: reorder() with its keys groups the batch by octant, stably, as a permutation of the batch.
TEST(Extending, ToyEncoderSortsTheBatchByOctant) {
  const Cornell c;
  GenerationStats stats;
  const RayBatch batch = c.toy_batch("toy_normal:order=scanline", stats);
  auto encoder = make_from(toy_encoders(), "encoder", "toy_octant", EncoderContext{c.scene.bounds, &c.bvh});
  RayBatch sorted;
  std::vector<uint32_t> order;
  ReorderTimings timings;
  ASSERT_TRUE(reorder(*encoder, batch, PermuteMode::Physical, sorted, order, timings));
  ASSERT_EQ(order.size(), batch.size());
  std::vector<uint32_t> seen(order);
  std::sort(seen.begin(), seen.end());
  std::vector<uint32_t> all(batch.size());
  std::iota(all.begin(), all.end(), 0u);
  EXPECT_EQ(seen, all);
  std::set<uint64_t> octants;
  for (size_t i = 0; i < order.size(); ++i) {
    EXPECT_EQ(sorted.rays[i].dir.x, batch.rays[order[i]].dir.x);
    octants.insert(octant_of(sorted.rays[i].dir));
    if (i == 0) continue;
    const uint64_t a = octant_of(sorted.rays[i - 1].dir), b = octant_of(sorted.rays[i].dir);
    EXPECT_LE(a, b) << "position " << i;
    if (a == b) {
      EXPECT_LT(order[i - 1], order[i]) << "not stable at " << i;
    }
  }
  EXPECT_GE(octants.size(), 3u);  // the walls face several ways, and scanline order mixes them: the sort had work
  EXPECT_FALSE(std::is_sorted(batch.rays.begin(), batch.rays.end(),
                              [](const Ray& a, const Ray& b) { return octant_of(a.dir) < octant_of(b.dir); }));
}

// The tracer: the same closest hits as the `cpu` tracer's BVH traversal, directly and through sorted indices.
TEST(Extending, ToyTracerFindsTheCpuTracersHits) {
  const Cornell c;
  GenerationStats stats;
  const RayBatch batch = c.toy_batch("toy_normal", stats);
  auto brute = make_from(toy_tracers(), "tracer", "toy_brute", c.scene, c.bvh);
  auto cpu = make_tracer({"cpu", ""}, c.scene, c.bvh);
  const std::vector<Hit> expected = trace_all(*cpu, batch), got = trace_all(*brute, batch);
  for (size_t i = 0; i < batch.size(); ++i) {
    ASSERT_EQ(got[i].valid(), expected[i].valid()) << "ray " << i;
    if (expected[i].valid()) {
      EXPECT_FLOAT_EQ(got[i].t, expected[i].t) << "ray " << i;
    }
  }
  std::vector<uint32_t> reversed(batch.size());
  std::iota(reversed.rbegin(), reversed.rend(), 0u);
  const std::vector<Hit> indirect = trace_all(*brute, batch, &reversed);
  for (size_t i = 0; i < batch.size(); ++i) EXPECT_EQ(indirect[i].prim, got[reversed[i]].prim) << "lane " << i;
}

// A GPU preset of simt/gpu_presets.cpp: named as listed, valid, at least one block resident, and the `simt`
// tracer's preset parameter accepts it.
TEST(Extending, EveryGpuPresetIsValidAndSelectable) {
  const Cornell c;
  for (const std::string& name : gpu_preset_names()) {
    SCOPED_TRACE(name);
    const GpuModelConfig g = gpu_preset(name);
    EXPECT_EQ(g.preset, name);
    EXPECT_NO_THROW(validate(g));
    EXPECT_GE(resident_warps(g), g.kernel.block_threads / 32);
    EXPECT_NE(make_tracer({"simt", "preset=" + name}, c.scene, c.bvh)->params().find("preset=" + name),
              std::string::npos);
  }
}

// A CSV column of records/experiment_row.cpp: results/README.md documents it in the table CSV's section.
TEST(Extending, EveryExperimentColumnIsDocumented) {
  std::ifstream in(std::string(RAYCOH_SOURCE_DIR) + "/results/README.md");
  ASSERT_TRUE(in) << "results/README.md";
  std::stringstream text;
  text << in.rdbuf();
  const std::string all = text.str();
  const size_t begin = all.find("## `raycoh table` and `raycoh sweep` CSV");
  ASSERT_NE(begin, std::string::npos);
  std::istringstream section(all.substr(begin, all.find("\n## ", begin + 1) - begin));
  std::set<std::string> documented;  // the names in the first cell of each table row: "| `a`, `b` | meaning |"
  for (std::string line; std::getline(section, line);) {
    if (line.rfind("| `", 0) != 0) continue;
    const std::string cell = line.substr(0, line.find(" |", 1));
    for (size_t a = cell.find('`'); a != std::string::npos; a = cell.find('`', cell.find('`', a + 1) + 1))
      documented.insert(cell.substr(a + 1, cell.find('`', a + 1) - a - 1));
  }
  for (const auto& column : experiment_schema()) EXPECT_EQ(documented.count(column.name), 1u) << column.name;
}

}  // namespace
}  // namespace raycoh
