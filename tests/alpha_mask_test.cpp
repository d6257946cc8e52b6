// Alpha MASK cut-outs as an any-hit test (core/alpha_mask.h): a glTF card whose texture is transparent on its left
// half, in front of a wall. Rays through the cut-out half hit the wall behind it, rays through the opaque half
// hit the card, on every host tracer (cpu and simt, BVH2 and CWBVH, embree) and in the double-precision
// reference (the cuda tracer where a GPU exists; tests/gpu_alpha_test.cpp compares it with cpu); a point light
// shines through the cut-out onto the wall and is blocked by the rest. Also: a MASK material without a texture
// is removed whole when its alpha is below the cutoff, a texture opaque everywhere needs no test, a scene without
// masks has no alpha arrays at all, and the cuda tracer's host check of the arrays it uploads.
#include "core/alpha_mask.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "cuda/trace_kernels.h"
#include "generators/generator.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "shading/path_tracer.h"
#include "tests/alpha_card.h"
#include "tests/scenes_test_util.h"
#include "tests/shading_test_util.h"
#include "tests/test_util.h"
#include "tracers/double_reference.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

TEST(AlphaMask, RaysThroughTheCutOutHitWhatIsBehindItOnEveryHostTracer) {
  const Scene s = load_scene(test::write_card("alpha_mask", "card.glb", test::kMaskCard).string());
  test::expect_valid(s);
  ASSERT_EQ(s.triangle_count(), 4u);
  EXPECT_EQ(s.alpha_cut_tris, 0u);
  ASSERT_FALSE(s.alpha.empty());
  EXPECT_EQ(s.alpha.masked_tris, 2u);
  EXPECT_TRUE(test::has_note(s, "alpha MASK: 2 triangle(s) of 1 material(s) cut out per texel"))
      << join(s.load_notes, " | ");
  // The card's material is its opaque (green) texels', not the mean with the transparent red ones.
  const Material& card = s.materials[s.tri_material[0]];
  EXPECT_LT(card.base_color.x, 0.25f);
  EXPECT_GT(card.base_color.y, 0.5f);

  const Bvh bvh = build_bvh(s);
  const std::vector<Ray> rays = test::rays_through_card();
  for (const char* name : {"cpu", "cpu:bvh=cwbvh", "simt", "simt:bvh=cwbvh", "embree", "embree:mode=packet16"}) {
    SCOPED_TRACE(name);
    auto tracer = make_tracer(parse_plugin_spec(name), s, bvh);
    std::vector<Hit> hits(rays.size());
    tracer->trace(rays.data(), rays.size(), hits.data());
    for (size_t i = 0; i < rays.size(); ++i) {
      ASSERT_TRUE(hits[i].valid()) << i;
      EXPECT_NEAR(hits[i].t, i < 5 ? 2.f : 1.f, 1e-6f) << i;
      EXPECT_EQ(hits[i].prim >= 2u, i < 5) << i;  // triangles 2 and 3 are the wall
    }
  }
  // The cuda tracer runs the same test in its kernels (gpu_alpha_test compares it with cpu on a device): here it
  // either traces the card as cpu does, or says that there is no CUDA build or device; it no longer refuses masks.
  {
    std::unique_ptr<Tracer> cuda;
    const std::string why = test::error_of([&] { cuda = make_tracer(parse_plugin_spec("cuda"), s, bvh); });
    if (cuda) {
      std::vector<Hit> hits(rays.size());
      cuda->trace(rays.data(), rays.size(), hits.data());
      for (size_t i = 0; i < rays.size(); ++i) EXPECT_NEAR(hits[i].t, i < 5 ? 2.f : 1.f, 1e-6f) << i;
    } else {
      EXPECT_TRUE(why.find("has no CUDA") != std::string::npos || why.find("no CUDA device") != std::string::npos)
          << why;
    }
  }
  for (size_t i = 0; i < rays.size(); ++i) {
    const AlphaMaskView view = s.alpha.view();
    EXPECT_NEAR(reference_closest_hit(bvh, rays[i], &view).t, i < 5 ? 2.0 : 1.0, 1e-9) << i;
    EXPECT_NEAR(reference_closest_hit(bvh, rays[i]).t, 1.0, 1e-9) << i;  // without the test: the card
  }
}

TEST(AlphaMask, LightShinesThroughTheCutOut) {
  // A point light in front of the card's middle, the camera between card and wall looking at the wall: behind the
  // cut-out half the wall is lit (L = albedo / pi x I cos / r^2, albedo 1), behind the opaque half it is in the
  // card's shadow. Direct light only.
  Scene s = load_scene(test::write_card("alpha_mask", "lit.glb", test::kMaskCard).string());
  s.lights = {PunctualLight{}};
  s.lights[0].position = {0.5f, 0.5f, 2.f};
  s.lights[0].intensity = Vec3(10.f);
  s.camera.from_file = true;
  s.camera.vfov_deg = 0.01f;
  finalize_scene(s);
  ASSERT_FALSE(s.env.enabled);
  const Bvh bvh = build_bvh(s);
  auto tracer = make_tracer(parse_plugin_spec("cpu"), s, bvh);
  auto gen = make_generator(parse_plugin_spec("noopt"));
  RenderSettings rs = test::small(2, 2);
  rs.max_depth = 1;
  auto wall_radiance = [&](float x) {
    s.camera.eye = {x, 0.5f, -0.5f};
    s.camera.target = {x, 0.5f, -1.f};
    PathTracer pt(s, *tracer, *gen, rs);
    Accumulator acc(2, 2);
    pt.render_frames(0, 1, acc);
    return acc.mean().at(0).y;
  };
  // x = 0.2: the path to the light crosses the card at x = 0.3, in the cut-out.
  const double r2 = 0.09 + 9.0, cos = 3.0 / std::sqrt(r2);
  EXPECT_NEAR(wall_radiance(0.2f), 10.0 * cos / r2 / M_PI, 1e-4);
  EXPECT_EQ(wall_radiance(0.8f), 0.f);  // crosses the card at x = 0.7, where it is opaque
}

TEST(AlphaMask, ConstantAlphaRemovesWholeTrianglesAndOpaqueTexturesNeedNoTest) {
  const Scene cut =
      load_scene(test::write_card(
                     "alpha_mask", "constant.glb",
                     R"({"alphaMode":"MASK","alphaCutoff":0.5,"pbrMetallicRoughness":{"baseColorFactor":[1,1,1,0.2]}})")
                     .string());
  EXPECT_EQ(cut.triangle_count(), 2u);
  EXPECT_EQ(cut.alpha_cut_tris, 2u);
  EXPECT_TRUE(cut.alpha.empty());
  EXPECT_TRUE(test::has_note(cut, "2 triangle(s) removed whole"));
  // A cutoff of 0: every texel passes.
  const Scene opaque =
      load_scene(test::write_card(
                     "alpha_mask", "opaque.glb",
                     R"({"alphaMode":"MASK","alphaCutoff":0,"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})")
                     .string());
  EXPECT_EQ(opaque.triangle_count(), 4u);
  EXPECT_TRUE(opaque.alpha.empty());
  // OPAQUE (the default) ignores alpha altogether.
  const Scene plain = load_scene(
      test::write_card("alpha_mask", "plain.glb", R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})")
          .string());
  EXPECT_TRUE(plain.alpha.empty());
}

// What the cuda tracer checks on the host before it uploads the mask arrays (a device read out of bounds would
// not be reported): the card's arrays pass; a missing entry, a texture index past the end and a texture past the
// texels are named.
TEST(AlphaMask, DeviceUploadCheckNamesInconsistentArrays) {
  const Scene s = load_scene(test::write_card("alpha_mask", "upload.glb", test::kMaskCard).string());
  const Bvh bvh = build_bvh(s);
  const AlphaMasks& m = s.alpha;
  const cuda::AlphaMaskArrays good{m.tri_texture.data(), m.tri_uv.data(), m.tri_texture.size(), m.textures.data(),
                                   m.textures.size(),    m.texels.data(), m.texels.size()};
  const BvhView v = bvh.view();
  EXPECT_EQ(cuda::alpha_arrays_error(good, v.tris, v.tri_count), "");

  cuda::AlphaMaskArrays short_arrays = good;
  short_arrays.tri_count = 2;  // the wall's triangles 2 and 3 have no entry
  EXPECT_NE(cuda::alpha_arrays_error(short_arrays, v.tris, v.tri_count).find("has no alpha entry"), std::string::npos);

  std::vector<uint32_t> bad_index = m.tri_texture;
  bad_index[1] = 7;
  cuda::AlphaMaskArrays bad_texture = good;
  bad_texture.tri_texture = bad_index.data();
  EXPECT_NE(cuda::alpha_arrays_error(bad_texture, v.tris, v.tri_count).find("names alpha texture 7 of 1"),
            std::string::npos);

  std::vector<AlphaTexture> past = m.textures;
  past[0].offset = m.texels.size() - 1;
  cuda::AlphaMaskArrays bad_offset = good;
  bad_offset.textures = past.data();
  EXPECT_NE(cuda::alpha_arrays_error(bad_offset, v.tris, v.tri_count).find("is not inside the"), std::string::npos);
}

TEST(AlphaMask, BilinearAlphaWithWrapModes) {
  // 4 x 1 texels with alpha 0, 0, 255, 255.
  const uint8_t texels[4] = {0, 0, 255, 255};
  AlphaTexture t;
  t.width = 4;
  t.height = 1;
  t.wrap_s = kWrapClamp;
  EXPECT_FLOAT_EQ(alpha_at(t, texels, 0.5f, 0.5f), 0.5f);
  EXPECT_FLOAT_EQ(alpha_at(t, texels, 0.f, 0.5f), 0.f);
  EXPECT_FLOAT_EQ(alpha_at(t, texels, 1.f, 0.5f), 1.f);
  EXPECT_FLOAT_EQ(alpha_at(t, texels, -3.f, 0.5f), 0.f);  // clamped
  t.wrap_s = kWrapRepeat;
  EXPECT_FLOAT_EQ(alpha_at(t, texels, 0.f, 0.5f), 0.5f);   // between texel 3 and texel 0
  EXPECT_FLOAT_EQ(alpha_at(t, texels, 7.75f, 0.5f), 1.f);  // texel 3 of a far repeat
  t.wrap_s = kWrapMirror;
  EXPECT_FLOAT_EQ(alpha_at(t, texels, 1.125f, 0.5f), 1.f);   // mirrored back onto texel 3
  EXPECT_FLOAT_EQ(alpha_at(t, texels, -0.125f, 0.5f), 0.f);  // mirrored onto texel 0
}

// Texture coordinates that are not finite, or so large that u x width overflows, read texel 0 in every wrap mode
// (converting them to int was undefined: fuzz_gltf, tests/fuzz/regressions/gltf/).
TEST(AlphaMask, NonFiniteTextureCoordinatesReadTexelZero) {
  const float bad[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                       -std::numeric_limits<float>::infinity(), 1e38f, -1e38f};
  for (uint32_t mode : {kWrapRepeat, kWrapClamp, kWrapMirror})
    for (float u : bad) {
      const BilinearTaps b = bilinear_taps(4, 3, mode, mode, u, 0.5f);
      EXPECT_EQ(b.xa, 0) << mode << " " << u;
      EXPECT_EQ(b.ax, 0.f) << mode << " " << u;
      EXPECT_TRUE(b.xb >= 0 && b.xb < 4) << mode << " " << u;
      EXPECT_TRUE(b.ya >= 0 && b.ya < 3 && b.yb >= 0 && b.yb < 3) << mode << " " << u;
    }
}

}  // namespace
}  // namespace raycoh
