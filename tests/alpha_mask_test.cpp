// Alpha MASK cut-outs as an any-hit test (core/alpha_mask.h): a glTF card whose texture is transparent on its left
// half, in front of a wall. Rays through the cut-out half hit the wall behind it, rays through the opaque half
// hit the card, on every host tracer (cpu and simt, BVH2 and CWBVH, embree) and in the double-precision
// reference (the cuda tracer refuses the scene); a point light shines through the cut-out onto the wall and is
// blocked by the rest. Also: a MASK
// material without a texture is removed whole when its alpha is below the cutoff, a texture opaque everywhere
// needs no test, and a scene without masks has no alpha arrays at all.
#include "core/alpha_mask.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "generators/generator.h"
#include "scenes/scene.h"
#include "shading/path_tracer.h"
#include "tests/scenes_test_util.h"
#include "tests/shading_test_util.h"
#include "tests/test_util.h"
#include "tracers/double_reference.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

namespace fs = std::filesystem;

// 4 x 1 RGBA PNG: texels 0 and 1 red with alpha 0, texels 2 and 3 green with alpha 255. Bilinear alpha crosses
// 0.5 at u = 0.5.
const std::vector<uint8_t> kHalfCutPng = {
    137, 80, 78, 71, 13,  10,  26, 10,  0,   0, 0,   13, 73, 72, 68, 82, 0,   0,   0,  4,   0,   0,   0,   1,  8,
    6,   0,  0,  0,  249, 60,  15, 205, 0,   0, 0,   17, 73, 68, 65, 84, 120, 218, 99, 248, 207, 192, 192, 0,  194,
    64,  2,  12, 1,  43,  229, 5,  251, 188, 8, 204, 4,  0,  0,  0,  0,  73,  69,  78, 68,  174, 66,  96,  130};

// The card: x, y in [0, 1] at z = 0 with u = x, v = y, material 0; the wall at z = -1, material 1. Material 0 is
// `card_material` (JSON), using texture 0 = kHalfCutPng.
fs::path write_card(const std::string& name, const std::string& card_material) {
  test::GltfWriter w;
  const int card = w.positions({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
  const int uv = w.add(std::vector<float>{0, 0, 1, 0, 1, 1, 0, 1}, 5126, "SCALAR");
  w.accessors[static_cast<size_t>(uv)] =
      fmt::format(R"({{"bufferView":{},"componentType":5126,"count":4,"type":"VEC2"}})", uv);
  const int wall = w.positions({-5, -5, -1, 5, -5, -1, 5, 5, -1, -5, 5, -1});
  const int idx = w.u16({0, 1, 2, 0, 2, 3});
  const int png = w.add(kHalfCutPng, 5121, "SCALAR");
  w.meshes = fmt::format(
      R"([{{"primitives":[{{"attributes":{{"POSITION":{0},"TEXCOORD_0":{1}}},"indices":{3},"material":0}},
                          {{"attributes":{{"POSITION":{2}}},"indices":{3},"material":1}}]}}])",
      card, uv, wall, idx);
  w.materials = fmt::format(R"([{},{{"name":"wall","pbrMetallicRoughness":{{"metallicFactor":0}}}}])", card_material);
  w.extra = fmt::format(
      R"(,"samplers":[{{"wrapS":33071,"wrapT":33071}}],"textures":[{{"source":0,"sampler":0}}],
          "images":[{{"bufferView":{},"mimeType":"image/png"}}])",
      png);
  return w.write("alpha_mask", name);
}

constexpr const char* kMaskCard =
    R"({"name":"card","alphaMode":"MASK","pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})";

// Rays along -z from z = 1 at x = 0.05, 0.15, ..., 0.95 (y = 0.5): the first five through the cut-out.
std::vector<Ray> rays_through_card() {
  std::vector<Ray> rays;
  for (int i = 0; i < 10; ++i) rays.push_back(Ray{{0.05f + 0.1f * i, 0.5f, 1.f}, 0.f, {0.f, 0.f, -1.f}, 10.f});
  return rays;
}

TEST(AlphaMask, RaysThroughTheCutOutHitWhatIsBehindItOnEveryHostTracer) {
  const Scene s = load_scene(write_card("card.glb", kMaskCard).string());
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
  const std::vector<Ray> rays = rays_through_card();
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
  // The GPU kernels do not test alpha: a CUDA build refuses the scene by name (before it looks for a GPU), a
  // build without CUDA has no such tracer.
  const std::string refused = test::error_of([&] { make_tracer(parse_plugin_spec("cuda"), s, bvh); });
  EXPECT_TRUE(refused.find("alpha MASK cut-outs") != std::string::npos ||
              refused.find("has no CUDA") != std::string::npos)
      << refused;
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
  Scene s = load_scene(write_card("lit.glb", kMaskCard).string());
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
  const Scene cut = load_scene(
      write_card("constant.glb",
                 R"({"alphaMode":"MASK","alphaCutoff":0.5,"pbrMetallicRoughness":{"baseColorFactor":[1,1,1,0.2]}})")
          .string());
  EXPECT_EQ(cut.triangle_count(), 2u);
  EXPECT_EQ(cut.alpha_cut_tris, 2u);
  EXPECT_TRUE(cut.alpha.empty());
  EXPECT_TRUE(test::has_note(cut, "2 triangle(s) removed whole"));
  // A cutoff of 0: every texel passes.
  const Scene opaque = load_scene(
      write_card("opaque.glb",
                 R"({"alphaMode":"MASK","alphaCutoff":0,"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})")
          .string());
  EXPECT_EQ(opaque.triangle_count(), 4u);
  EXPECT_TRUE(opaque.alpha.empty());
  // OPAQUE (the default) ignores alpha altogether.
  const Scene plain =
      load_scene(write_card("plain.glb", R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})").string());
  EXPECT_TRUE(plain.alpha.empty());
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

}  // namespace
}  // namespace raycoh
