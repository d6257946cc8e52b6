// Alpha MASK cut-outs on the GPU (cuda/trace_kernels.cu): the `cuda` tracer uploads a masked scene's alpha arrays
// and every kernel (persistent, simple, counting; BVH2 and CWBVH) runs core/alpha_mask.h's AlphaTest, so its hits
// equal the `cpu` tracer's bit for bit: on the card with a cut-out half of alpha_mask_test (rays through the hole
// hit the wall), and, where the glTF sample folder is present, on AlphaBlendModeTest and GlassVaseFlowers
// (primary and NoOpt secondary rays, direct and shuffled indirect). Each scene must have rays whose hit the mask
// changes, so a kernel that ignored the mask fails. The counting kernel's counters equal the `simt` tracer's on
// the masked scenes too. Skips cleanly (GTEST_SKIP) without a CUDA device. Label `gpu`.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/flush_denormals.h"
#include "core/rng.h"
#include "core/traverse.h"
#include "cuda/cuda_device.h"
#include "cuda/trace_kernels.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "generators/primary.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "tests/alpha_card.h"
#include "tests/gpu_test_size.h"
#include "tests/test_util.h"
#include "tests/trace_test_util.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

using test::differing_hits;
using test::trace_with;

namespace fs = std::filesystem;

#define SKIP_WITHOUT_GPU() \
  if (cuda::device_count() == 0) GTEST_SKIP() << "no CUDA device"

struct MaskedScene {
  std::string name;
  Scene scene;
  Bvh bvh;
  std::vector<Ray> rays;  // primary rays, then the NoOpt secondary rays made from their hits
};

// Primary rays of a small image in tile order and the NoOpt secondary batch from their (cpu) hits.
void add_frame_rays(MaskedScene& m) {
  const int width = test::gpu_test_size(160, 40), height = test::gpu_test_size(120, 30);
  auto cpu = make_tracer({"cpu", ""}, m.scene, m.bvh);
  const PixelRays primary = make_primary_rays(m.scene.camera, width, height,
                                              make_pixel_order(width, height, RayOrder::Tile, 8, 8), 1, 0, true);
  std::vector<Hit> hits(primary.rays.size());
  cpu->trace(primary.rays.data(), hits.size(), hits.data());
  const GBuffer g = make_gbuffer(m.scene, primary, hits);
  RayBatch secondary;
  GenerationStats stats;
  make_generator({"noopt", ""})->generate(m.scene, g, 1, secondary, stats);
  m.rays.assign(primary.rays.begin(), primary.rays.end());
  m.rays.insert(m.rays.end(), secondary.rays.begin(), secondary.rays.end());
}

// The card (10 rays through both halves, repeated to more than one warp with a partial last one), and the
// masked glTF samples that are present.
std::vector<std::unique_ptr<MaskedScene>> masked_scenes() {
  std::vector<std::unique_ptr<MaskedScene>> out;
  auto card = std::make_unique<MaskedScene>();
  card->name = "card";
  card->scene = load_scene(test::write_card("gpu_alpha", "card.glb", test::kMaskCard).string());
  card->bvh = build_bvh(card->scene);
  const std::vector<Ray> ten = test::rays_through_card();
  for (int k = 0; k < 7; ++k) card->rays.insert(card->rays.end(), ten.begin(), ten.end());
  out.push_back(std::move(card));

  const fs::path samples = test::gltf_samples_dir();
  for (const char* name : {"AlphaBlendModeTest", "GlassVaseFlowers"}) {
    const fs::path file = samples / name / "glTF-Binary" / (std::string(name) + ".glb");
    if (!fs::exists(file)) continue;
    auto m = std::make_unique<MaskedScene>();
    m->name = name;
    m->scene = load_scene(file.string());
    m->bvh = build_bvh(m->scene);
    add_frame_rays(*m);
    out.push_back(std::move(m));
  }
  return out;
}

std::vector<uint32_t> shuffled_order(size_t n) {
  std::vector<uint32_t> order(n);
  for (size_t i = 0; i < n; ++i) order[i] = static_cast<uint32_t>(i);
  for (size_t i = n; i > 1; --i) std::swap(order[i - 1], order[rng_u32(5, 0, static_cast<uint32_t>(i), 0) % i]);
  return order;
}

// The scene's masks decide some hits: the cpu tracer (with the test) and the bare traversal (without) differ.
TEST(GpuAlphaMask, TheScenesHaveHitsThatTheMaskDecides) {
  for (const auto& m : masked_scenes()) {
    SCOPED_TRACE(m->name);
    ASSERT_FALSE(m->scene.alpha.empty());
    auto cpu = make_tracer({"cpu", ""}, m->scene, m->bvh);
    const std::vector<Hit> with = trace_with(*cpu, m->rays);
    std::vector<Hit> without(m->rays.size());
    const FlushDenormalsScope ftz;
    for (size_t i = 0; i < m->rays.size(); ++i) without[i] = closest_hit(m->bvh.view(), m->rays[i]);
    EXPECT_GT(differing_hits(with, without), 0u);
  }
}

// Every kernel, block size, layout and order of the cuda tracer against the cpu tracer of the same layout.
TEST(GpuAlphaMask, CudaHitsEqualTheCpuTracerOnMaskedScenes) {
  SKIP_WITHOUT_GPU();
  for (const auto& m : masked_scenes()) {
    const std::vector<uint32_t> order = shuffled_order(m->rays.size());
    for (const char* layout : {"bvh2", "cwbvh"}) {
      auto cpu = make_tracer({"cpu", std::string("bvh=") + layout}, m->scene, m->bvh);
      const std::vector<Hit> want = trace_with(*cpu, m->rays), want_indirect = trace_with(*cpu, m->rays, &order);
      for (const std::string kernel : {"kernel=persistent,block=128", "kernel=simple,block=64", "traversal=classic",
                                       "counters=on", "stack=shared"}) {
        const bool bvh2_only = kernel == "traversal=classic" || kernel == "counters=on";
        if ((std::string(layout) == "cwbvh" && bvh2_only) ||
            (std::string(layout) == "bvh2" && kernel == "stack=shared"))
          continue;
        const std::string params = kernel + ",bvh=" + layout;
        SCOPED_TRACE(m->name + " cuda:" + params);
        auto gpu = make_tracer({"cuda", params}, m->scene, m->bvh);
        EXPECT_EQ(differing_hits(trace_with(*gpu, m->rays), want), 0u);
        EXPECT_EQ(differing_hits(trace_with(*gpu, m->rays, &order), want_indirect), 0u);
      }
    }
    if (m->name == "card") {  // through the hole: the wall at t = 2; the opaque half: the card at t = 1
      auto gpu = make_tracer({"cuda", ""}, m->scene, m->bvh);
      const std::vector<Hit> hits = trace_with(*gpu, m->rays);
      for (size_t i = 0; i < hits.size(); ++i) EXPECT_NEAR(hits[i].t, i % 10 < 5 ? 2.f : 1.f, 1e-6f) << i;
    }
  }
}

// The DeviceTracer API: with the arrays it tests the masks, without them it runs the unmasked kernels, whose
// hits are the bare traversal's (what the cuda tracer gave before masks).
TEST(GpuAlphaMask, DeviceTracerTestsMasksOnlyWhenGivenTheArrays) {
  SKIP_WITHOUT_GPU();
  const auto scenes = masked_scenes();
  const MaskedScene& m = *scenes.back();
  const AlphaMasks& a = m.scene.alpha;
  ASSERT_FALSE(a.tri_texture.empty()) << m.name << " has no alpha MASK arrays (texture not decoded?)";
  const cuda::AlphaMaskArrays arrays{a.tri_texture.data(), a.tri_uv.data(), a.tri_texture.size(), a.textures.data(),
                                     a.textures.size(),    a.texels.data(), a.texels.size()};
  cuda::DeviceTracer masked(m.bvh.view(), arrays), plain(m.bvh.view());
  EXPECT_TRUE(masked.alpha_masked());
  EXPECT_FALSE(plain.alpha_masked());
  std::vector<Hit> with(m.rays.size()), without(m.rays.size()), bare(m.rays.size()), filtered(m.rays.size());
  masked.trace(m.rays.data(), nullptr, m.rays.size(), with.data(), cuda::TraceLaunch{});
  plain.trace(m.rays.data(), nullptr, m.rays.size(), without.data(), cuda::TraceLaunch{});
  {
    const FlushDenormalsScope ftz;
    const AlphaTest alpha{a.view()};
    NoCounters none;
    for (size_t i = 0; i < m.rays.size(); ++i) {
      bare[i] = closest_hit(m.bvh.view(), m.rays[i]);
      filtered[i] = closest_hit(m.bvh.view(), m.rays[i], none, alpha);
    }
  }
  EXPECT_EQ(differing_hits(with, filtered), 0u);
  EXPECT_EQ(differing_hits(without, bare), 0u);
  EXPECT_GT(differing_hits(with, without), 0u);
}

// The counting kernel runs the filter too: its hits and counters equal the simt tracer's (which tests the masks
// the same way and counts no texel reads).
TEST(GpuAlphaMask, CountingKernelEqualsSimtOnMaskedScenes) {
  SKIP_WITHOUT_GPU();
  for (const auto& m : masked_scenes()) {
    SCOPED_TRACE(m->name);
    auto gpu = make_tracer({"cuda", "counters=on,line=64"}, m->scene, m->bvh);
    auto simt = make_tracer({"simt", "line=64"}, m->scene, m->bvh);
    EXPECT_EQ(differing_hits(trace_with(*gpu, m->rays), trace_with(*simt, m->rays)), 0u);
    const CoherenceCounters& g = *gpu->last_counters();
    const CoherenceCounters& s = *simt->last_counters();
    EXPECT_EQ(g.rays, s.rays);
    EXPECT_EQ(g.node_steps, s.node_steps);
    EXPECT_EQ(g.leaf_steps, s.leaf_steps);
    EXPECT_EQ(g.triangle_steps, s.triangle_steps);
    EXPECT_EQ(g.node_lanes, s.node_lanes);
    EXPECT_EQ(g.triangle_lanes, s.triangle_lanes);
    EXPECT_EQ(g.node_lines, s.node_lines);
    EXPECT_EQ(g.triangle_fetches, s.triangle_fetches);
    EXPECT_EQ(g.nodes, s.nodes);
    EXPECT_EQ(g.triangles, s.triangles);
  }
}

}  // namespace
}  // namespace raycoh
