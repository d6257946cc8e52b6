// Punctual lights (glTF KHR_lights_punctual, shading/emitters.h): a diffuse floor lit by a point, a spot, a
// directional light and two point lights of unequal power converges to the analytic radiance
// L = albedo / pi x E, E = I cos / r^2 (point, spot with the spec's cone falloff and range window) or E cos
// (directional), at fixed seeds; occluders cast shadows and objects beyond a light do not; a scene lit only by
// punctual lights gets no sky. The glTF loader places lights at their nodes (scale ignored), refuses malformed
// ones by name, and reports them.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "bvh/bvh_build.h"
#include "generators/generator.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "shading/emitters.h"
#include "shading/path_tracer.h"
#include "tests/scenes_test_util.h"
#include "tests/shading_test_util.h"
#include "tests/test_util.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

using test::small;

constexpr double kPiD = 3.14159265358979323846;

// Appends a quad whose winding faces n.
void add_quad(Scene& s, Vec3 p0, Vec3 p1, Vec3 p2, Vec3 p3, Vec3 n, uint32_t material) {
  if (dot(cross(p1 - p0, p2 - p0), n) < 0.f) std::swap(p1, p3);
  const uint32_t base = static_cast<uint32_t>(s.positions.size());
  for (Vec3 p : {p0, p1, p2, p3}) {
    s.positions.push_back(p);
    s.normals.push_back(n);
  }
  s.indices.insert(s.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  s.tri_material.insert(s.tri_material.end(), {material, material});
}

constexpr Vec3 kAlbedo{0.5f, 0.6f, 0.7f};
constexpr Vec3 kLook{0.f, 0.f, -1.f};  // the floor point every camera ray hits

// A huge diffuse floor at y = 0 seen from (0, 1, 0) through a field of view so narrow that every pixel sees kLook,
// lit by `lights` only.
Scene lit_floor(const std::vector<PunctualLight>& lights) {
  Scene s;
  s.name = "floor";
  s.source = "test";
  Material m;
  m.name = "floor";
  m.base_color = kAlbedo;
  s.materials = {m};
  const float e = 1000.f;
  add_quad(s, {-e, 0.f, -e}, {e, 0.f, -e}, {e, 0.f, e}, {-e, 0.f, e}, {0.f, 1.f, 0.f}, 0);
  s.camera.eye = {0.f, 1.f, 0.f};
  s.camera.target = kLook;
  s.camera.vfov_deg = 0.01f;
  s.camera.from_file = true;
  s.lights = lights;
  finalize_scene(s);
  return s;
}

PunctualLight point(Vec3 at, Vec3 intensity) {
  PunctualLight l;
  l.name = "p";
  l.type = LightType::Point;
  l.position = at;
  l.intensity = intensity;
  return l;
}

// Mean radiance over the image of `frames` frames (max depth 3: the floor cannot see itself, so only direct
// light arrives).
Vec3 mean_radiance(const Scene& scene, int frames, FrameStats* stats = nullptr) {
  const Bvh bvh = build_bvh(scene);
  auto tracer = make_tracer(parse_plugin_spec("cpu"), scene, bvh);
  auto gen = make_generator(parse_plugin_spec("noopt"));
  RenderSettings rs = small(8, 8);
  rs.max_depth = 3;
  PathTracer pt(scene, *tracer, *gen, rs);
  Accumulator acc(rs.width, rs.height);
  const FrameStats st = pt.render_frames(0, frames, acc);
  if (stats) *stats = st;
  EXPECT_EQ(acc.non_finite_samples(), 0u);
  const Image img = acc.mean();
  double sum[3] = {0, 0, 0};
  for (size_t p = 0; p < img.pixels(); ++p)
    for (int c = 0; c < 3; ++c) sum[c] += img.at(p)[c];
  const double n = static_cast<double>(img.pixels());
  return {static_cast<float>(sum[0] / n), static_cast<float>(sum[1] / n), static_cast<float>(sum[2] / n)};
}

// albedo / pi x E, with E = I cos / r^2 x window for a light at `at` seen from kLook.
Vec3 expected_from(Vec3 at, Vec3 intensity, double window = 1.0) {
  const Vec3 d = at - kLook;
  const double r2 = dot(d, d), cos = d.y / std::sqrt(r2);
  const double e = cos / r2 * window / kPiD;
  return {static_cast<float>(kAlbedo.x * intensity.x * e), static_cast<float>(kAlbedo.y * intensity.y * e),
          static_cast<float>(kAlbedo.z * intensity.z * e)};
}

void expect_near_rel(Vec3 got, Vec3 want, double rel) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], rel * want[c]) << "channel " << c;
}

TEST(PunctualLights, PointLightOverADiffuseFloorGivesAlbedoOverPiTimesIcosOverR2) {
  // One light: the choice has probability 1 and the narrow view fixes the point, so every sample is exact up to
  // float rounding (1e-4 relative).
  const Vec3 at{0.3f, 2.f, -0.5f}, intensity{50.f, 40.f, 30.f};
  const Scene s = lit_floor({point(at, intensity)});
  EXPECT_FALSE(s.env.enabled);  // lit by its light, not by a substituted sky
  FrameStats st;
  expect_near_rel(mean_radiance(s, 2, &st), expected_from(at, intensity), 1e-4);
  EXPECT_EQ(st.shadow_rays, 2u * 64);  // one per first hit; the bounce rays leave the scene

  // Range: the spec's window clamp(1 - (d / range)^4, 0, 1); beyond the range nothing arrives.
  PunctualLight ranged = point(at, intensity);
  ranged.range = 3.f;
  const double d = length(at - kLook), x = d / 3.0;
  expect_near_rel(mean_radiance(lit_floor({ranged}), 1), expected_from(at, intensity, 1.0 - x * x * x * x), 1e-4);
  ranged.range = 2.f;
  EXPECT_EQ(mean_radiance(lit_floor({ranged}), 1).y, 0.f);
}

TEST(PunctualLights, TwoUnequalPointLightsConvergeThroughPowerProportionalChoice) {
  // The choice is random now (probabilities 0.8 and 0.2 by power): 64 pixels x 16 frames = 1024 samples of a
  // two-valued estimator (11.1 or 13.6 x albedo / pi) whose standard error is 0.3% of the mean; the tolerance
  // is 2%.
  const Vec3 a{0.3f, 2.f, -0.5f}, b{-1.f, 0.5f, -1.5f};
  const Vec3 ia{40.f, 40.f, 40.f}, ib{10.f, 10.f, 10.f};
  const Scene s = lit_floor({point(a, ia), point(b, ib)});
  const EmitterDistribution lights(s);
  ASSERT_EQ(lights.punctual.pmf.size(), 2u);
  EXPECT_NEAR(lights.punctual.pmf[0], 0.8f, 1e-6f);
  const Vec3 want = expected_from(a, ia) + expected_from(b, ib);
  expect_near_rel(mean_radiance(s, 16), want, 0.02);
}

TEST(PunctualLights, SpotConeFalloffFollowsTheSpec) {
  // A spot 2 above kLook, its axis tilted by 20 degrees; cone 10..30 degrees: the falloff is
  // t^2, t = (cos 20 - cos 30) / (cos 10 - cos 30); tilted by 35 degrees nothing arrives.
  const Vec3 at{0.f, 2.f, -1.f}, intensity{30.f, 30.f, 30.f};
  auto spot = [&](double tilt_deg) {
    PunctualLight l = point(at, intensity);
    l.type = LightType::Spot;
    const double t = tilt_deg * kPiD / 180.0;
    l.direction = {static_cast<float>(std::sin(t)), static_cast<float>(-std::cos(t)), 0.f};
    l.cos_inner = static_cast<float>(std::cos(10.0 * kPiD / 180.0));
    l.cos_outer = static_cast<float>(std::cos(30.0 * kPiD / 180.0));
    return l;
  };
  const double c20 = std::cos(20.0 * kPiD / 180.0), c10 = std::cos(10.0 * kPiD / 180.0),
               c30 = std::cos(30.0 * kPiD / 180.0);
  const double t = (c20 - c30) / (c10 - c30);
  expect_near_rel(mean_radiance(lit_floor({spot(20.0)}), 1), expected_from(at, intensity, t * t), 1e-3);
  expect_near_rel(mean_radiance(lit_floor({spot(5.0)}), 1), expected_from(at, intensity), 1e-4);
  EXPECT_EQ(mean_radiance(lit_floor({spot(35.0)}), 1).y, 0.f);
}

TEST(PunctualLights, DirectionalLightGivesAlbedoOverPiTimesEcos) {
  PunctualLight sun;
  sun.type = LightType::Directional;
  sun.direction = normalize(Vec3{-0.3f, -1.f, 0.2f});
  sun.intensity = {2.f, 3.f, 4.f};
  const Scene s = lit_floor({sun});
  EXPECT_FALSE(s.env.enabled);
  const double cos = -static_cast<double>(s.lights[0].direction.y);
  const Vec3 want{static_cast<float>(kAlbedo.x * 2.0 * cos / kPiD), static_cast<float>(kAlbedo.y * 3.0 * cos / kPiD),
                  static_cast<float>(kAlbedo.z * 4.0 * cos / kPiD)};
  expect_near_rel(mean_radiance(s, 2), want, 1e-4);
}

TEST(PunctualLights, OccludersCastShadowsAndGeometryBeyondTheLightDoesNot) {
  const Vec3 at{0.f, 1.5f, -1.f}, intensity(20.f);
  Scene s = lit_floor({point(at, intensity)});
  // A card between the light and kLook (y = 1, small) and a ceiling beyond the light (y = 3).
  Scene blocked = s;
  add_quad(blocked, {-0.1f, 1.f, -1.1f}, {0.1f, 1.f, -1.1f}, {0.1f, 1.f, -0.9f}, {-0.1f, 1.f, -0.9f}, {0.f, -1.f, 0.f},
           0);
  blocked.camera.eye = {0.f, 0.5f, 0.f};  // below the card
  finalize_scene(blocked);
  EXPECT_EQ(mean_radiance(blocked, 1).y, 0.f);
  Scene ceiling = s;
  add_quad(ceiling, {-50.f, 3.f, -50.f}, {50.f, 3.f, -50.f}, {50.f, 3.f, 50.f}, {-50.f, 3.f, 50.f}, {0.f, -1.f, 0.f},
           0);
  finalize_scene(ceiling);
  RenderSettings direct = small(8, 8);
  // Direct light only (the ceiling reflects light back down at later bounces).
  const Bvh bvh = build_bvh(ceiling);
  auto tracer = make_tracer(parse_plugin_spec("cpu"), ceiling, bvh);
  auto gen = make_generator(parse_plugin_spec("noopt"));
  direct.max_depth = 1;
  PathTracer pt(ceiling, *tracer, *gen, direct);
  Accumulator acc(8, 8);
  pt.render_frames(0, 1, acc);
  expect_near_rel(acc.mean().at(0), expected_from(at, intensity), 1e-4);
}

TEST(PunctualLights, GltfLightsSitAtTheirNodesAndAreReported) {
  test::GltfWriter w;
  const int pos = w.positions({-5, 0, -5, 5, 0, -5, 5, 0, 5, -5, 0, 5});
  const int idx = w.u16({0, 2, 1, 0, 3, 2});
  w.meshes = test::mesh_json(pos, idx);
  // Node 1: a point light 2 above the origin inside a node scaled by 5 (scale does not change a light).
  // Node 2: a spot aimed down (-Z rotated to -Y by 90 degrees about +X). Node 3: a directional light with the
  // default orientation (travelling along -Z). Node 4: a light with zero intensity (dropped, noted).
  w.nodes = R"([{"mesh":0},
                {"translation":[0,2,0],"scale":[5,5,5],"extensions":{"KHR_lights_punctual":{"light":0}}},
                {"translation":[1,3,0],"rotation":[-0.70710678,0,0,0.70710678],
                 "extensions":{"KHR_lights_punctual":{"light":1}}},
                {"extensions":{"KHR_lights_punctual":{"light":2}}},
                {"extensions":{"KHR_lights_punctual":{"light":3}}}])";
  w.scenes = R"([{"nodes":[0,1,2,3,4]}])";
  w.extra = R"(,"extensionsUsed":["KHR_lights_punctual"],"extensions":{"KHR_lights_punctual":{"lights":[
      {"type":"point","color":[1,0.5,0.25],"intensity":8,"range":10,"name":"bulb"},
      {"type":"spot","intensity":3,"spot":{"innerConeAngle":0.2,"outerConeAngle":0.5}},
      {"type":"directional","intensity":2},
      {"type":"point","intensity":0}]}})";
  const Scene s = load_scene(w.write("gltf_lights", "lights.glb").string());
  test::expect_valid(s);
  ASSERT_EQ(s.lights.size(), 3u);
  EXPECT_FALSE(s.env.enabled);
  const PunctualLight& bulb = s.lights[0];
  EXPECT_EQ(bulb.name, "bulb");
  EXPECT_EQ(bulb.type, LightType::Point);
  EXPECT_NEAR(bulb.position.y, 2.f, 1e-6f);
  EXPECT_NEAR(bulb.intensity.y, 4.f, 1e-6f);
  EXPECT_EQ(bulb.range, 10.f);
  const PunctualLight& spot = s.lights[1];
  EXPECT_EQ(spot.type, LightType::Spot);
  EXPECT_NEAR(spot.direction.y, -1.f, 1e-5f);
  EXPECT_NEAR(spot.position.x, 1.f, 1e-6f);
  EXPECT_NEAR(spot.cos_outer, std::cos(0.5f), 1e-6f);
  EXPECT_EQ(s.lights[2].type, LightType::Directional);
  EXPECT_NEAR(s.lights[2].direction.z, -1.f, 1e-6f);
  EXPECT_TRUE(test::has_note(s, "extension KHR_lights_punctual: supported"));
  EXPECT_TRUE(test::has_note(s, "3 light(s) traced (1 point, 1 spot, 1 directional)"));
  EXPECT_TRUE(test::has_note(s, "1 with zero intensity dropped"));
  const SceneFeatures f = analyse(s);
  EXPECT_EQ(f.punctual_lights, 3u);

  // Malformed lights are one-line errors naming the file and the light.
  test::GltfWriter bad = w;
  bad.extra = R"(,"extensions":{"KHR_lights_punctual":{"lights":[{"type":"area"}]}})";
  bad.nodes = R"([{"mesh":0},{"extensions":{"KHR_lights_punctual":{"light":0}}}])";
  bad.scenes = R"([{"nodes":[0,1]}])";
  test::expect_load_error(bad.write("gltf_lights", "area.glb"), "type 'area'");
  bad.nodes = R"([{"mesh":0},{"extensions":{"KHR_lights_punctual":{"light":4}}}])";
  test::expect_load_error(bad.write("gltf_lights", "missing.glb"), "refers to light 4");
  bad.extra = R"(,"extensions":{"KHR_lights_punctual":{"lights":[
      {"type":"spot","spot":{"innerConeAngle":0.6,"outerConeAngle":0.5}}]}})";
  bad.nodes = R"([{"mesh":0},{"extensions":{"KHR_lights_punctual":{"light":0}}}])";
  test::expect_load_error(bad.write("gltf_lights", "cone.glb"), "inner <= outer");
}

TEST(PunctualLights, RebasedScenesKeepTheirIrradiance) {
  // A tiny scene (1/32 across) is scaled up by 32 in finalize_scene: the point light's intensity scales by 32^2,
  // so the image is unchanged.
  const float k = 1.f / 64.f;
  Scene s;
  s.name = "tiny";
  s.source = "test";
  Material m;
  m.base_color = kAlbedo;
  s.materials = {m};
  add_quad(s, {-k, 0.f, -k}, {k, 0.f, -k}, {k, 0.f, k}, {-k, 0.f, k}, {0.f, 1.f, 0.f}, 0);
  s.camera.eye = {0.f, k, k};
  s.camera.target = {0.f, 0.f, 0.f};
  s.camera.vfov_deg = 0.01f;
  s.camera.from_file = true;
  s.lights = {point({0.f, 0.5f * k, 0.f}, Vec3(1.f))};
  finalize_scene(s);
  ASSERT_EQ(s.rebase_scale, 32.f);
  // E = I / r^2 at the origin straight below: 1 / (k / 2)^2. The light is only 0.25 away after scaling, so the
  // shadow ray's origin offset moves the result by about 1e-4; forgetting the scale^2 would be a factor 1024.
  const double e = 1.0 / (0.25 * k * k);
  const Vec3 got = mean_radiance(s, 1);
  EXPECT_NEAR(got.y, kAlbedo.y / kPiD * e, 1e-3 * kAlbedo.y / kPiD * e);
}

}  // namespace
}  // namespace raycoh
