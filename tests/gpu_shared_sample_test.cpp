// `sadeghi` and `microjitter` on the device (cuda/device_generators.h: the per-pixel kernel with the numbers rule of
// generators/shared_sample.h) where the paper-protocol runs use them: the device pipeline (`cuda` with
// pipeline=device, and its fused form pipeline=fused, which makes and traces each tile's rays in one kernel)
// accepts them and its batch, statistics and hits equal the host pipeline's (the CPU generator on the device's own
// G-buffer, traced by the `cpu` tracer) bit for bit; the device path tracer accepts them and its first bounce equals
// the CPU generator's on the CPU camera pass. The batch-for-batch test over stiff G-buffers is
// GpuGenerators.SharedSampleBatchesEqualTheCpuByteForByte. Small (48x32, 16x16 under RAYCOH_GPU_TEST_SIZE=sim); skips
// without a device. Label `gpu`.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "cuda/cuda_device.h"
#include "cuda/device_path_tracer.h"
#include "cuda/device_pipeline.h"
#include "encoders/encoder.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "shading/emitters.h"
#include "tests/batch_test_util.h"
#include "tests/gpu_test_size.h"
#include "tests/test_util.h"
#include "tests/trace_test_util.h"
#include "tracers/device_pipeline.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

#define SKIP_WITHOUT_GPU() \
  if (cuda::device_count() == 0) GTEST_SKIP() << "no CUDA device"

constexpr uint32_t kSeed = 5, kFrame = 2;

// Interleave 1 and 4, two radii, and the scanline order (one-row tiles).
const std::vector<std::string>& shared_specs() {
  static const std::vector<std::string> specs = {"sadeghi", "sadeghi:interleave=4", "microjitter",
                                                 "microjitter:radius=0.5,order=scanline"};
  return specs;
}

TEST(GpuSharedSample, TheDevicePipelineMakesAndTracesTheHostPipelinesBatch) {
  SKIP_WITHOUT_GPU();
  const int width = test::gpu_test_size(48, 16), height = test::gpu_test_size(32, 16);
  for (const char* name : {"cornell", "voxels:size=16"})
    for (const char* form : {"pipeline=device", "pipeline=fused"}) {
      SCOPED_TRACE(std::string(name) + " " + form);
      const Scene scene = load_scene(name);
      const Bvh bvh = build_bvh(scene);
      auto cpu = make_tracer({"cpu", ""}, scene, bvh);
      auto cuda = make_tracer({"cuda", form}, scene, bvh);
      DevicePipeline* pipeline = cuda->device_pipeline();
      ASSERT_NE(pipeline, nullptr) << "pipeline=device is the default";
      pipeline->primary(width, height, 8, 8, kSeed, kFrame, true);
      pipeline->first_hits_gbuffer();
      const GBuffer g = pipeline->download_gbuffer();  // equal to the host's (GpuPipeline.CameraRaysHitsAndGBuffer...)
      ASSERT_GT(g.hits, 0u);
      auto none = make_encoder({"none", ""}, EncoderContext{scene.bounds, &bvh});
      for (const std::string& spec : shared_specs()) {
        SCOPED_TRACE(spec);
        auto generator = make_generator(parse_plugin_spec(spec));
        ASSERT_EQ(pipeline->refusal(spec, *generator, *none), "");
        RayBatch host, generated, permuted;
        GenerationStats host_stats, device_stats;
        generator->generate(scene, g, kSeed, host, host_stats);
        pipeline->secondary(*generator, *none, PermuteMode::Physical, kSeed, device_stats);
        std::vector<uint32_t> order;
        std::vector<Hit> hits;
        pipeline->download_secondary(generated, order, permuted, hits);
        test::expect_same_columns(generated, host);
        EXPECT_EQ(device_stats.rays, host_stats.rays);
        EXPECT_EQ(device_stats.below_geometric, host_stats.below_geometric);
        EXPECT_EQ(device_stats.below_shading, host_stats.below_shading);
        EXPECT_EQ(device_stats.non_finite, host_stats.non_finite);
        EXPECT_EQ(device_stats.reused_rays, host_stats.reused_rays);
        EXPECT_EQ(device_stats.reused_rays, host.size());  // interleave 4: 16 streams for hundreds of pixels
        EXPECT_EQ(test::differing_hits(hits, test::trace_with(*cpu, host.rays)), 0u);
      }
    }
}

TEST(GpuSharedSample, TheDevicePathTracersFirstBounceEqualsTheCpuGenerators) {
  SKIP_WITHOUT_GPU();
  constexpr uint32_t kPathFrame = 3;
  for (const char* name : {"cornell", "voxels:size=24"}) {
    const Scene scene = load_scene(name);
    const Bvh bvh = build_bvh(scene);
    const EmitterDistribution lights(scene);
    auto cpu = make_tracer({"cpu", ""}, scene, bvh);
    const cuda::DevicePathSettings settings{test::gpu_test_size(64, 16), test::gpu_test_size(48, 16), 7,
                                            test::gpu_test_size(5, 3), 2};
    const FirstHits first =
        first_hits(scene, *cpu, settings.width, settings.height,
                   make_pixel_order(settings.width, settings.height, RayOrder::Tile, 8, 8), settings.seed, kPathFrame);
    for (const std::string& spec : shared_specs()) {
      SCOPED_TRACE(std::string(name) + " " + spec);
      auto generator = make_generator(parse_plugin_spec(spec));
      cuda::DevicePathTracer device(scene, bvh, lights.view(scene), *generator, settings);
      std::vector<Vec3> radiance;
      device.render_frame(kPathFrame, radiance);
      EXPECT_EQ(radiance.size(), static_cast<size_t>(settings.width) * settings.height);
      RayBatch gpu, host;
      device.download_first_bounce(gpu);
      GenerationStats stats;
      generator->generate(scene, first.gbuffer, settings.seed, host, stats);
      ASSERT_GT(host.size(), 0u);
      test::expect_same_columns(gpu, host);
    }
  }
}

}  // namespace
}  // namespace raycoh
