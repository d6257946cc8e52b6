// The device path tracer's fused first bounce (cuda/device_path_tracer.h, DevicePathSettings::fused; --device
// cuda:pipeline=fused): one kernel per tile makes each first-bounce ray and traces it from shared memory, and also
// writes the batch the wave's shading reads. Against the materialized first bounce (the batch written by the device
// generator, then traced by the trace kernel) on the same seed: the first-bounce batch byte for byte, the
// generation statistics, the ray counts and every frame's radiance bit for bit, for noopt, ours (tile and group
// order), contiguous, sadeghi and microjitter (scanline order too), on built-in scenes and an alpha-masked glTF sample
// (the fused kernel's any-hit test) when the samples are there. The materialized path equals the CPU's
// (tests/gpu_path_tracer_test.cpp), so the fused one does too. ours / contiguous in scanline order have no fused form
// (a block makes one tile's rays): refused in one line before anything reaches the device. Label `gpu`; skips without a
// device.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "cuda/cuda_device.h"
#include "cuda/device_path_tracer.h"
#include "generators/generator.h"
#include "scenes/scene.h"
#include "shading/emitters.h"
#include "tests/batch_test_util.h"
#include "tests/gpu_path_tracer_util.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

#define SKIP_WITHOUT_GPU() \
  if (cuda::device_count() == 0) GTEST_SKIP() << "no CUDA device"

std::vector<std::string> fused_scenes() {
  std::vector<std::string> scenes = {"cornell", "voxels:size=24"};
  const std::filesystem::path dir = test::gltf_samples_dir();
  const std::filesystem::path masked = dir / "AlphaBlendModeTest" / "glTF-Binary" / "AlphaBlendModeTest.glb";
  if (!dir.empty() && std::filesystem::exists(masked)) scenes.push_back(masked.string());
  return scenes;
}

cuda::DevicePathSettings fused_settings(const RenderSettings& rs) {
  cuda::DevicePathSettings s = test::device_settings(rs);
  s.fused = true;
  return s;
}

void expect_same_batch(const RayBatch& fused, const RayBatch& materialized) {
  ASSERT_GT(materialized.size(), 0u);
  test::expect_same_columns(fused, materialized);
}

void expect_same_stats(const cuda::DeviceFrameStats& f, const cuda::DeviceFrameStats& m) {
  EXPECT_EQ(f.rays.primary, m.rays.primary);
  EXPECT_EQ(f.rays.secondary, m.rays.secondary);
  EXPECT_EQ(f.rays.bounce, m.rays.bounce);
  EXPECT_EQ(f.rays.shadow, m.rays.shadow);
  EXPECT_EQ(f.rays.second, m.rays.second);
  // The first two bounces' wave traces are parts of the trace stage in either form.
  for (const cuda::DeviceFrameStats* s : {&f, &m}) {
    EXPECT_GE(s->stages.first_wave_trace_ms, 0.f);
    EXPECT_GE(s->stages.second_wave_trace_ms, 0.f);
    EXPECT_LE(s->stages.first_wave_trace_ms + s->stages.second_wave_trace_ms, s->stages.trace_ms * (1.f + 1e-5f));
  }
  EXPECT_EQ(f.generation.rays, m.generation.rays);
  EXPECT_EQ(f.generation.reused_rays, m.generation.reused_rays);
  EXPECT_EQ(f.generation.below_geometric, m.generation.below_geometric);
  EXPECT_EQ(f.generation.non_finite, m.generation.non_finite);
  for (int t = 0; t < 5; ++t) EXPECT_EQ(f.generation.groups[t], m.generation.groups[t]) << "group type " << t;
}

TEST(GpuFusedPath, FirstBounceAndFramesEqualTheMaterializedPathBitForBit) {
  SKIP_WITHOUT_GPU();
  const std::vector<PluginSpec> generators = {{"noopt", ""},      {"ours", ""},    {"ours", "order=group"},
                                              {"contiguous", ""}, {"sadeghi", ""}, {"microjitter", "order=scanline"}};
  for (const std::string& spec : fused_scenes()) {
    SCOPED_TRACE(spec);
    const Scene scene = load_scene(spec);
    const Bvh bvh = build_bvh(scene);
    const EmitterDistribution lights(scene);
    const RenderSettings rs = test::path_settings(5);
    for (const PluginSpec& g : generators) {
      SCOPED_TRACE(g.text());
      auto generator = make_generator(g);
      cuda::DevicePathTracer materialized(scene, bvh, lights.view(scene), *generator, test::device_settings(rs));
      cuda::DevicePathTracer fused(scene, bvh, lights.view(scene), *generator, fused_settings(rs));
      std::vector<Vec3> m_radiance, f_radiance;
      for (uint32_t frame = 0; frame < 2; ++frame) {
        SCOPED_TRACE(frame);
        const cuda::DeviceFrameStats m = materialized.render_frame(frame, m_radiance);
        const cuda::DeviceFrameStats f = fused.render_frame(frame, f_radiance);
        RayBatch m_batch, f_batch;
        materialized.download_first_bounce(m_batch);
        fused.download_first_bounce(f_batch);
        expect_same_batch(f_batch, m_batch);
        expect_same_stats(f, m);
        EXPECT_EQ(test::differing(f_radiance, m_radiance), 0u);
      }
    }
  }
}

// A fused block makes one tile's rays: ours and contiguous in scanline order are refused when the path tracer is
// made, in one line naming the way out, before any device call (so this runs without a device too).
TEST(GpuFusedPath, ScanlineGroupingHasNoFusedFormAndIsRefused) {
  const Scene scene = load_scene("cornell");
  const Bvh bvh = build_bvh(scene);
  const EmitterDistribution lights(scene);
  const RenderSettings rs = test::path_settings(1);
  for (const PluginSpec& g : std::vector<PluginSpec>{{"ours", "order=scanline"}, {"contiguous", "order=scanline"}}) {
    SCOPED_TRACE(g.text());
    auto generator = make_generator(g);
    const std::string why = test::error_of(
        [&] { cuda::DevicePathTracer fused(scene, bvh, lights.view(scene), *generator, fused_settings(rs)); });
    EXPECT_NE(why.find("no fused form"), std::string::npos) << why;
    EXPECT_NE(why.find("cuda:pipeline=device"), std::string::npos) << why;
    EXPECT_EQ(why.find('\n'), std::string::npos) << why;
  }
}

}  // namespace
}  // namespace raycoh
