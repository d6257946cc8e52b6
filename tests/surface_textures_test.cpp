// Materials looked up per texel at the hit (core/surface_textures.h): the class, BSDF parameters and emission of a
// shading point follow the texel it hit, emissive texels weigh emitter sampling, normal maps tilt the shading
// normal, and scenes without textures get their triangles' materials exactly as before.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "core/srgb_decode.h"
#include "generators/generator.h"
#include "generators/primary.h"
#include "scenes/scene.h"
#include "shading/emitters.h"
#include "tests/scenes_test_util.h"

namespace raycoh {
namespace {

using test::GltfWriter;

// 2 x 2 RGBA PNG: top row white, bottom row black (both opaque).
const std::vector<uint8_t> kTwoRowPng = {
    137, 80,  78, 71, 13,  10,  26, 10,  0,  0,   0,  13,  73, 72, 68, 82, 0,   0,   0,  2,   0,   0,  0,  2,  8,
    6,   0,   0,  0,  114, 182, 13, 36,  0,  0,   0,  17,  73, 68, 65, 84, 120, 156, 99, 248, 15,  5,  12, 64, 0,
    34,  254, 3,  0,  113, 160, 9,  247, 61, 251, 21, 187, 0,  0,  0,  0,  73,  69,  78, 68,  174, 66, 96, 130};

// Triangles in the z = 0 plane (xyz per vertex, 3 vertices a triangle) with TEXCOORD_0 uv, one material using
// kTwoRowPng as texture 0.
Scene textured(const std::string& name, const std::vector<float>& xyz, const std::vector<float>& uv,
               const std::string& material, const std::string& sampler = "") {
  GltfWriter w;
  const int pos = w.positions(xyz);
  const int tc = w.add(uv, 5126, "SCALAR");
  w.accessors[static_cast<size_t>(tc)] =
      fmt::format(R"({{"bufferView":{},"componentType":5126,"count":{},"type":"VEC2"}})", tc, uv.size() / 2);
  const int png = w.add(kTwoRowPng, 5121, "SCALAR");
  w.meshes =
      fmt::format(R"([{{"primitives":[{{"attributes":{{"POSITION":{},"TEXCOORD_0":{}}},"material":0}}]}}])", pos, tc);
  w.materials = "[" + material + "]";
  w.extra = fmt::format(R"(,"textures":[{{"source":0{}}}],"images":[{{"bufferView":{},"mimeType":"image/png"}}])",
                        sampler.empty() ? "" : ",\"sampler\":0", png);
  if (!sampler.empty()) w.extra += ",\"samplers\":[" + sampler + "]";
  return load_scene(w.write("surface_textures", name + ".glb").string());
}

// One triangle (0,0,0) (1,0,0) (0,1,0) whose texture coordinates equal its (x, y).
const std::vector<float> kUnitTri = {0, 0, 0, 1, 0, 0, 0, 1, 0};
const std::vector<float> kUnitUv = {0, 0, 1, 0, 0, 1};

// The G-buffer of hits on triangle 0 at barycentrics (b1, b2), seen from +z straight down.
GBuffer hits_at(const Scene& scene, const std::vector<std::pair<float, float>>& bary) {
  PixelRays rays;
  rays.width = static_cast<int>(bary.size());
  rays.height = 1;
  std::vector<Hit> hits;
  for (size_t i = 0; i < bary.size(); ++i) {
    Ray r;
    r.org = {bary[i].first, bary[i].second, 1.f};
    r.dir = {0.f, 0.f, -1.f};
    rays.rays.push_back(r);
    rays.pixel.push_back(static_cast<uint32_t>(i));
    Hit h;
    h.t = 1.f;
    h.prim = 0;
    h.u = bary[i].first;
    h.v = bary[i].second;
    hits.push_back(h);
  }
  return make_gbuffer(scene, rays, hits);
}

TEST(SurfaceTextures, ClassFollowsTheTexelAtTheHit) {
  // Metallic-roughness texture: top row metal + rough (glossy by metalness), bottom row smooth dielectric.
  const Scene s = textured("metal_rough", kUnitTri, kUnitUv,
                           R"({"pbrMetallicRoughness":{"metallicFactor":1,"roughnessFactor":1,
                               "metallicRoughnessTexture":{"index":0}}})");
  ASSERT_EQ(s.triangle_count(), 1u);
  ASSERT_FALSE(s.textures.empty());
  // v = 0.25 and 0.75 are the texel rows' centres (bilinear gives the pure texel there).
  const GBuffer g = hits_at(s, {{0.25f, 0.25f}, {0.1f, 0.75f}});
  ASSERT_TRUE(g.points[0].valid() && g.points[1].valid());
  ASSERT_TRUE(g.materials && g.materials->per_hit());
  const BsdfParams& top = g.materials->bsdf[g.points[0].material];
  const BsdfParams& bottom = g.materials->bsdf[g.points[1].material];
  EXPECT_EQ(g.points[0].cls, MaterialClass::Glossy);
  EXPECT_EQ(top.cls, MaterialClass::Glossy);
  EXPECT_FLOAT_EQ(top.metallic, 1.f);
  EXPECT_FLOAT_EQ(top.roughness, 1.f);
  EXPECT_EQ(g.points[1].cls, MaterialClass::Specular);
  EXPECT_EQ(bottom.cls, MaterialClass::Specular);
  EXPECT_FLOAT_EQ(bottom.metallic, 0.f);
  EXPECT_FLOAT_EQ(bottom.roughness, 0.f);
  // The generators read the point's class: the batch's material column follows the texel.
  RayBatch batch;
  GenerationStats stats;
  make_generator(parse_plugin_spec("noopt"))->generate(s, g, 1, batch, stats);
  ASSERT_EQ(batch.size(), 2u);
  for (size_t i = 0; i < batch.size(); ++i) EXPECT_EQ(batch.material[i], g.points[batch.pixel[i]].cls);
}

TEST(SurfaceTextures, EmissiveTexelsDecideEmissionAndEmitterPower) {
  // Triangle A (x in [0, 1]) samples the white row only; triangle B (x in [2, 3]), of the same area and factor,
  // runs from the white row's centre at its first corner to the black row's centre at the other two, so its mean
  // emission is the mean of srgb_to_linear(1 - b2)-like bilinear values: integral of 2 y f(y), f = srgb_to_linear.
  const std::vector<float> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 3, 0, 0, 2, 1, 0};
  const std::vector<float> uv = {0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.75f};
  const Scene s = textured("emissive", xyz, uv, R"({"emissiveFactor":[2,2,2],"emissiveTexture":{"index":0}})",
                           R"({"wrapS":33071,"wrapT":33071})");
  ASSERT_EQ(s.triangle_count(), 2u);
  ASSERT_EQ(s.emissive_tris.size(), 2u);
  double mean_b = 0.0;
  const int n = 100000;
  for (int i = 0; i < n; ++i) {
    const double y = (i + 0.5) / n;
    mean_b += 2.0 * y * srgb_to_linear(static_cast<float>(y)) / n;
  }
  const EmitterDistribution e(s);
  ASSERT_EQ(e.tris.size(), 2u);
  // The factor alone would give both triangles the same probability.
  EXPECT_NEAR(e.pmf_by_prim[1] / e.pmf_by_prim[0], mean_b, 0.03 * mean_b);
  // At a hit the emission is the texel's: full at B's white corner, none at its black edge.
  const SurfaceTexturesView view = s.textures.view();
  EXPECT_NEAR(surface_at(view, 1, 0.f, 0.f).emission.x, 2.f, 1e-4f);
  EXPECT_NEAR(surface_at(view, 1, 0.f, 1.f).emission.x, 0.f, 1e-6f);
  EXPECT_NE(surface_at(view, 1, 0.f, 1.f).bsdf.cls, MaterialClass::Emissive);
  EXPECT_EQ(surface_at(view, 1, 0.f, 0.f).bsdf.cls, MaterialClass::Emissive);
  // Next-event estimation's point carries the emission of its texel too.
  ShadingPoint sp;
  sp.position = {2.2f, 0.2f, 1.f};
  sp.ng = sp.ns = {0.f, 0.f, 1.f};
  for (float u : {0.05f, 0.5f, 0.95f}) {
    const EmitterSample es = e.sample(s, sp, 0.99f, u, 0.5f);  // 0.99: triangle B (the cdf's last entry)
    ASSERT_TRUE(es.found || es.pdf == 0.f);
    if (!es.found) continue;
    const float su = std::sqrt(u), b1 = 1.f - su, b2 = 0.5f * su;
    EXPECT_FLOAT_EQ(es.emission.x, surface_at(view, 1, b1, b2).emission.x);
  }
}

// Radical inverse in base b of i (a low-discrepancy coordinate).
double radical_inverse(uint32_t i, uint32_t b) {
  double r = 0.0, f = 1.0 / b;
  for (; i > 0; i /= b, f /= b) r += f * (i % b);
  return r;
}

TEST(SurfaceTextures, NextEventEstimationOfTexturedEmittersIsUnbiased) {
  // The pmf weighs triangles by their mean emission and samples them uniformly by area, but a sample carries its
  // texel's emission: the estimator L(y) cos_x / pdf must still average to the integral of L(y) cos_x cos_y / d^2
  // over both triangles. A receiver close to B's bright corner makes the texel matter: B's mean there would be
  // about a third too low. Reference: both triangles integrated directly (area-uniform grid, no pmf, no pdf).
  const std::vector<float> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 3, 0, 0, 2, 1, 0};
  const std::vector<float> uv = {0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.75f};
  const Scene s = textured("emissive_nee", xyz, uv, R"({"emissiveFactor":[2,2,2],"emissiveTexture":{"index":0}})",
                           R"({"wrapS":33071,"wrapT":33071})");
  const EmitterDistribution e(s);
  ASSERT_EQ(e.tris.size(), 2u);
  const SurfaceTexturesView view = s.textures.view();
  const Vec3 x{2.1f, 0.1f, 0.15f};  // the receiver, facing -z (down onto the emitters, which face +z)
  ShadingPoint sp;
  sp.position = x;
  sp.ng = sp.ns = {0.f, 0.f, -1.f};
  const uint32_t n = 1u << 16;
  double nee = 0.0, worst_pdf = 0.0;
  for (uint32_t i = 0; i < n; ++i) {
    const float u_pick = static_cast<float>((i + 0.5) / n);
    const EmitterSample es =
        e.sample(s, sp, u_pick, static_cast<float>(radical_inverse(i, 2)), static_cast<float>(radical_inverse(i, 3)));
    if (!es.found) continue;
    nee += es.emission.x * -es.dir.z / es.pdf / n;
    // What multiple importance sampling weighs a BSDF hit at that point with (hit_gathering.cpp) is this pdf.
    const float hit_pdf = e.pdf(e.tris[e.pick(u_pick)], es.dist, -es.dir.z);
    worst_pdf = std::max(worst_pdf, std::fabs(hit_pdf / es.pdf - 1.0));
  }
  EXPECT_LT(worst_pdf, 1e-4);
  double direct = 0.0, direct_mean = 0.0;
  const int m = 256;
  for (uint32_t t = 0; t < 2; ++t) {
    const uint32_t* idx = &s.indices[3 * t];
    const Vec3 v0 = s.positions[idx[0]], v1 = s.positions[idx[1]], v2 = s.positions[idx[2]];
    const double area = 0.5 * length(cross(v1 - v0, v2 - v0));
    for (int a = 0; a < m; ++a) {
      for (int b = 0; b < m; ++b) {
        const float su = std::sqrt((a + 0.5f) / m), b1 = 1.f - su, b2 = (b + 0.5f) / m * su;  // area-uniform
        const Vec3 d = v0 * (1.f - b1 - b2) + v1 * b1 + v2 * b2 - x;
        const double d2 = dot(d, d), g = (x.z * x.z) / (d2 * d2);  // cos_x cos_y / d^2, both cosines h / d
        direct += area / (m * m) * surface_at(view, t, b1, b2).emission.x * g;
        direct_mean += area / (m * m) * s.textures.tri_emission[t].x * g;
      }
    }
  }
  EXPECT_NEAR(nee, direct, 0.01 * direct) << "triangle means alone would give " << direct_mean;
  EXPECT_GT(std::fabs(direct_mean - direct), 0.1 * direct);  // the test can tell texels from means
}

TEST(SurfaceTextures, NormalMapTiltsTheShadingNormal) {
  // normalTexture: white texels (1, 1, 1) are n_ts = (scale, scale, 1), black ones (-scale, -scale, -1), which
  // points below the surface and is not used. On this triangle the tangent (+u) is +x and the bitangent (+Y of a
  // glTF normal map, up the image: -v) is -y.
  const Scene s = textured("normal_map", kUnitTri, kUnitUv, R"({"normalTexture":{"index":0,"scale":0.5}})");
  ASSERT_FALSE(s.textures.empty());
  const GBuffer g = hits_at(s, {{0.25f, 0.25f}, {0.1f, 0.75f}});
  const Vec3 expected = normalize(Vec3{0.5f, -0.5f, 1.f});
  EXPECT_LT(length(g.points[0].ns - expected), 1e-5f) << g.points[0].ns.x << " " << g.points[0].ns.y;
  EXPECT_LT(length(g.points[0].ng - Vec3{0.f, 0.f, 1.f}), 1e-6f);
  EXPECT_LT(length(g.points[1].ns - Vec3{0.f, 0.f, 1.f}), 1e-6f);  // the guard: the interpolated normal stays
  // Without a map the same triangle keeps its interpolated normal.
  const Scene plain =
      textured("no_normal_map", kUnitTri, kUnitUv, R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})");
  EXPECT_LT(length(hits_at(plain, {{0.25f, 0.25f}}).points[0].ns - Vec3{0.f, 0.f, 1.f}), 1e-6f);
}

TEST(SurfaceTextures, ScenesWithoutTexturesKeepTheirTrianglesMaterials) {
  const Scene s = load_scene("cornell");
  ASSERT_TRUE(s.textures.empty());
  for (uint32_t prim = 0; prim < s.triangle_count(); ++prim) {
    PixelRays rays;
    rays.width = 1;
    rays.height = 1;
    Ray r;
    r.dir = {0.f, 0.f, -1.f};
    rays.rays = {r};
    rays.pixel = {0};
    Hit h;
    h.t = 1.f;
    h.prim = prim;
    h.u = 0.2f;
    h.v = 0.3f;
    const GBuffer g = make_gbuffer(s, rays, {h});
    const ShadingPoint& sp = g.points[0];
    ASSERT_TRUE(g.materials && !g.materials->per_hit());
    EXPECT_EQ(sp.material, s.tri_material[prim]);
    const Material& m = s.materials[s.tri_material[prim]];
    const BsdfParams& b = g.materials->bsdf[sp.material];
    EXPECT_EQ(sp.cls, m.cls);
    EXPECT_EQ(b.cls, m.cls);
    EXPECT_EQ(b.base_color.x, m.base_color.x);
    EXPECT_EQ(b.roughness, m.roughness);
    EXPECT_EQ(b.metallic, m.metallic);
    EXPECT_EQ(g.materials->emission[sp.material].y, m.emission.y);
  }
}

// The sRGB decode (core/srgb_decode.h) against the formula in double, on every float of the power segment
// (0.04045, 1] and a little beyond (a filtered texel may round above 1), and on every 64th float of the linear
// segment: within 1 ulp of the true value (measured: 0.78 ulp on the power segment, 0.56 on the linear one), and
// never decreasing from 0.03 to 1 (across the segments' seam and the table's interval ends).
TEST(SurfaceTextures, SrgbDecodeIsWithinOneUlpOfTheFormulaOnEveryFloat) {
  auto ulps = [](float f, double y) {
    int e;
    std::frexp(y, &e);  // y in [2^(e-1), 2^e): a float's ulp there is 2^(e-24)
    return std::fabs(static_cast<double>(f) - y) / std::ldexp(1.0, std::max(e - 24, -149));
  };
  double power = 0.0, linear = 0.0;
  size_t decreasing = 0, n = 0;
  float previous = srgb_to_linear(0.03f);
  for (uint32_t bits = std::bit_cast<uint32_t>(0.03f); bits <= std::bit_cast<uint32_t>(1.0001f); ++bits, ++n) {
    const float c = std::bit_cast<float>(bits), f = srgb_to_linear(c);
    decreasing += f < previous;
    previous = f;
    if (c > 0.04045f) power = std::max(power, ulps(f, std::pow((static_cast<double>(c) + 0.055) / 1.055, 2.4)));
  }
  for (uint32_t bits = 0; std::bit_cast<float>(bits) <= 0.04045f; bits += 64)
    linear = std::max(linear, ulps(srgb_to_linear(std::bit_cast<float>(bits)), std::bit_cast<float>(bits) / 12.92));
  std::printf("sRGB decode over %zu floats in [0.03, 1.0001]: max %.3f ulp (power), %.3f ulp (linear)\n", n, power,
              linear);
  EXPECT_GT(n, 40000000u);
  EXPECT_LE(power, 1.0);
  EXPECT_LE(linear, 1.0);
  EXPECT_EQ(decreasing, 0u);
  EXPECT_EQ(srgb_to_linear(0.f), 0.f);
  EXPECT_EQ(srgb_to_linear(1.f), 1.f);
  EXPECT_EQ(srgb_to_linear(INFINITY), INFINITY);
  EXPECT_TRUE(std::isnan(srgb_to_linear(NAN)));
  EXPECT_LE(ulps(srgb_to_linear(100.f), std::pow(100.055 / 1.055, 2.4)), 1.0) << "the reduction is general";
}

// Each table entry is its definition: T(r, j) = 1.055^-2.4 2^(0.4 r) m0^2.4 as the float nearest it plus the float
// nearest the rest, 1 / m0 rounded (m0 = 1 + (j + 1/2) / 16), against long double.
TEST(SurfaceTextures, SrgbDecodeTableIsItsDefinition) {
  const SrgbPowTable& t = srgb_pow_table();
  for (int j = 0; j < 16; ++j) {
    SCOPED_TRACE(j);
    const long double m0 = 1.0L + (j + 0.5L) / 16.0L;
    EXPECT_EQ(t.recip[j], static_cast<float>(1.0L / m0));
    for (int r = 0; r < 5; ++r) {
      const long double v = std::pow(1.055L, -2.4L) * std::exp2(0.4L * r) * std::pow(m0, 2.4L);
      EXPECT_EQ(t.hi[16 * r + j], static_cast<float>(v)) << r;
      EXPECT_EQ(t.lo[16 * r + j], static_cast<float>(v - t.hi[16 * r + j])) << r;
    }
  }
}

}  // namespace
}  // namespace raycoh
