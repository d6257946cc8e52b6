// The camera pass's G-buffer made on the device (cuda/device_gbuffer.h) against make_gbuffer (generators/primary.h)
// on the same camera rays and hits, bit for bit, whole G-buffers: every field of every ShadingPoint and every entry
// of the material table (the scene's materials, then one slot per pixel in textured scenes), hit count and layout
// (tests/gbuffer_test_util.h), sRGB-decoded texels included (core/srgb_decode.h: the same float operations on both
// sides, where powf rounded 1 ulp apart). Scenes: built-in ones, the alpha MASK card (a base-colour texture), the
// glTF samples with textures, normal and emissive maps and alpha masks, and the shared sibenik_lamps when they are
// there. The device path tracer keeps its G-buffer on the device: downloaded, it equals make_gbuffer of its own
// camera rays and hits, frame after frame; and its first bounce on the textured scenes (whose base colours pick the
// lobe and weigh the rays) equals the CPU generator's on the CPU camera pass, bit for bit, as does the frame. Label
// `gpu`; skips without a device. RAYCOH_GPU_TEST_SIZE=sim: 24x16 pixels.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "cuda/cuda_device.h"
#include "cuda/device_gbuffer.h"
#include "cuda/device_path_tracer.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "generators/primary.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "shading/emitters.h"
#include "shading/path_tracer.h"
#include "tests/alpha_card.h"
#include "tests/batch_test_util.h"
#include "tests/block_stats_util.h"
#include "tests/gbuffer_test_util.h"
#include "tests/gpu_test_size.h"
#include "tests/test_util.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

using test::differing;

namespace fs = std::filesystem;

#define SKIP_WITHOUT_GPU() \
  if (cuda::device_count() == 0) GTEST_SKIP() << "no CUDA device"

constexpr uint32_t kSeed = 11, kFrame = 4;

int width() { return test::gpu_test_size(64, 24); }
int height() { return test::gpu_test_size(48, 16); }

// Built-in scenes, the card, and the glTF samples and shared scene that are present.
std::vector<std::string> gbuffer_scenes() {
  std::vector<std::string> specs = {"cornell", "voxels:size=16", "slivers"};
  specs.push_back(test::write_card("gpu_gbuffer", "card.glb", test::kMaskCard).string());
  const fs::path dir = test::gltf_samples_dir();
  for (const char* name : {"DamagedHelmet", "AlphaBlendModeTest", "BoxTextured"}) {
    const fs::path glb = dir / name / "glTF-Binary" / (std::string(name) + ".glb");
    const fs::path gltf = dir / name / "glTF" / (std::string(name) + ".gltf");
    if (dir.empty()) continue;
    if (fs::exists(glb))
      specs.push_back(glb.string());
    else if (fs::exists(gltf))
      specs.push_back(gltf.string());
  }
  for (const auto& path : test::shared_scene_files())
    if (path.filename() == "sibenik_lamps.glb") specs.push_back(path.string());
  return specs;
}

TEST(GpuGBuffer, EqualsMakeGbufferBitForBit) {
  SKIP_WITHOUT_GPU();
  int textured = 0;
  for (const std::string& spec : gbuffer_scenes()) {
    SCOPED_TRACE(spec);
    const Scene scene = load_scene(spec);
    const Bvh bvh = build_bvh(scene);
    auto cpu = make_tracer({"cpu", ""}, scene, bvh);
    const auto order = make_pixel_order(width(), height(), RayOrder::Tile, 8, 8);
    const FirstHits host = first_hits(scene, *cpu, width(), height(), order, kSeed, kFrame);
    ASSERT_GT(host.gbuffer.hits, 0u);
    const GBuffer device = cuda::make_gbuffer_gpu(scene, host.primary, host.hits);
    const test::GBufferDiff diff = test::compare_gbuffers(device, host.gbuffer);
    EXPECT_EQ(diff.total(), 0u) << diff.summary();
    std::printf("%s: %s\n", spec.c_str(), diff.summary().c_str());
    ASSERT_TRUE(device.materials);
    EXPECT_EQ(device.materials->per_hit(), !scene.textures.empty());
    textured += device.materials->per_hit();
  }
  EXPECT_GT(textured, 0) << "the card is textured: the per-pixel table slots must be compared";
}

// The comparison sees one flipped bit in a point, in a table entry's BSDF and in its emission, sRGB-decoded
// channels of a per-pixel slot included.
TEST(GpuGBuffer, TheComparisonSeesOneBit) {
  const Scene scene = load_scene(test::write_card("gpu_gbuffer", "card.glb", test::kMaskCard).string());
  const Bvh bvh = build_bvh(scene);
  auto cpu = make_tracer({"cpu", ""}, scene, bvh);
  const FirstHits host = first_hits(scene, *cpu, 16, 16, make_pixel_order(16, 16, RayOrder::Tile, 8, 8), kSeed, kFrame);
  ASSERT_TRUE(host.gbuffer.materials && host.gbuffer.materials->per_hit());
  auto flipped = [](float f) { return std::bit_cast<float>(std::bit_cast<uint32_t>(f) ^ 1u); };
  GBuffer a = host.gbuffer;
  a.points[3].ns.y = flipped(a.points[3].ns.y);
  EXPECT_EQ(test::compare_gbuffers(a, host.gbuffer).points, 1u);
  GBuffer b = host.gbuffer;
  auto table = std::make_shared<HitMaterials>(*host.gbuffer.materials);
  table->bsdf.back().roughness = flipped(table->bsdf.back().roughness);
  table->emission.front().z = flipped(table->emission.front().z);
  b.materials = table;
  const test::GBufferDiff d = test::compare_gbuffers(b, host.gbuffer);
  EXPECT_EQ(d.bsdf, 1u);
  EXPECT_EQ(d.emission, 1u);
  EXPECT_EQ(d.points + d.header, 0u);
  // One ulp in the last per-pixel slot's base colour (an sRGB-decoded texel) and in its emission.
  GBuffer c = host.gbuffer;
  auto near = std::make_shared<HitMaterials>(*host.gbuffer.materials);
  ASSERT_GT(near->bsdf.size(), near->scene_count);
  near->bsdf.back().base_color.x = flipped(near->bsdf.back().base_color.x);
  near->emission.back().y = flipped(near->emission.back().y);
  c.materials = near;
  const test::GBufferDiff strict = test::compare_gbuffers(c, host.gbuffer);
  EXPECT_EQ(strict.bsdf, 1u);
  EXPECT_EQ(strict.emission, 1u);
  EXPECT_EQ(strict.total(), 2u);
}

// The device path tracer's G-buffer stays on the device; downloaded after a frame it is make_gbuffer of that
// frame's camera rays and hits (a second frame overwrites the first's in place).
TEST(GpuGBuffer, ThePathTracersDeviceGBufferEqualsMakeGbuffer) {
  SKIP_WITHOUT_GPU();
  for (const std::string& spec : {std::string("cornell"), gbuffer_scenes()[3]}) {
    SCOPED_TRACE(spec);
    const Scene scene = load_scene(spec);
    const Bvh bvh = build_bvh(scene);
    const EmitterDistribution lights(scene);
    auto generator = make_generator({"ours", ""});
    cuda::DevicePathTracer device(scene, bvh, lights.view(scene), *generator, {width(), height(), kSeed, 2, 2});
    std::vector<Vec3> radiance;
    for (uint32_t frame : {kFrame, kFrame + 1}) {
      device.render_frame(frame, radiance);
      PixelRays rays;
      std::vector<Hit> hits;
      device.download_camera(rays, hits);
      ASSERT_EQ(rays.frame, frame);
      const GBuffer host = make_gbuffer(scene, rays, hits);
      ASSERT_GT(host.hits, 0u);
      const test::GBufferDiff diff = test::compare_gbuffers(device.download_gbuffer(), host);
      EXPECT_EQ(diff.total(), 0u) << "frame " << frame << ": " << diff.summary();
    }
  }
}

// The device path tracer's first bounce (its camera pass, G-buffer and generator) on the textured scenes equals the
// CPU's (first_hits, then the generator), bit for bit in every column of the batch (test::expect_same_columns:
// rays, pixels, pdfs, weights, normals, material classes and ours's tile, group and group type), for noopt (each
// pixel's own lobe, chosen by its base colour) and ours; and so does the whole frame's radiance, the CPU path
// tracer's with the same seed and settings (every texel decoded on the paths' later hits too).
TEST(GpuGBuffer, FirstBounceRaysAndFramesOnTexturedScenesEqualTheCpuBitForBit) {
  SKIP_WITHOUT_GPU();
  int textured = 0;
  for (const std::string& spec : gbuffer_scenes()) {
    const Scene scene = load_scene(spec);
    if (scene.textures.empty()) continue;
    ++textured;
    const Bvh bvh = build_bvh(scene);
    const EmitterDistribution lights(scene);
    auto cpu = make_tracer({"cpu", ""}, scene, bvh);
    const auto order = make_pixel_order(width(), height(), RayOrder::Tile, 8, 8);
    const FirstHits first = first_hits(scene, *cpu, width(), height(), order, kSeed, kFrame);
    for (const char* gen : {"noopt", "ours"}) {
      SCOPED_TRACE(spec + " " + gen);
      auto generator = make_generator({gen, ""});
      RenderSettings rs;
      rs.width = width();
      rs.height = height();
      rs.seed = kSeed;
      rs.max_depth = 2;
      rs.rr_depth = 2;
      cuda::DevicePathTracer device(scene, bvh, lights.view(scene), *generator,
                                    {rs.width, rs.height, rs.seed, rs.max_depth, rs.rr_depth});
      std::vector<Vec3> radiance;
      device.render_frame(kFrame, radiance);
      PathTracer pt(scene, *cpu, *generator, rs);
      Accumulator acc(rs.width, rs.height);
      pt.render_frame(kFrame, acc);
      EXPECT_EQ(differing(radiance, test::frame_samples(acc)), 0u) << "the frame's radiance";
      RayBatch gpu, host;
      device.download_first_bounce(gpu);
      GenerationStats stats;
      generator->generate(scene, first.gbuffer, kSeed, host, stats);
      ASSERT_GT(host.size(), 0u);
      test::expect_same_columns(gpu, host);
      std::printf("%s %s: %zu first-bounce rays equal\n", spec.c_str(), gen, host.size());
    }
  }
  EXPECT_GT(textured, 0) << "the card is textured";
}

}  // namespace
}  // namespace raycoh
