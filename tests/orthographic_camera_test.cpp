// The orthographic camera (Camera::ortho_half_height, generators/primary_ray.h): parallel rays from the plane
// through the eye, covering half-height h and half-width h x aspect; the view survives the origin rebase; a
// floor seen through it under a directional light is uniformly lit.
#include <gtest/gtest.h>

#include <numeric>
#include <vector>

#include "bvh/bvh_build.h"
#include "generators/generator.h"
#include "generators/primary.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "shading/path_tracer.h"
#include "tests/shading_test_util.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

Camera ortho(Vec3 eye, Vec3 target, float half_height) {
  Camera c;
  c.eye = eye;
  c.target = target;
  c.up = {0.f, 1.f, 0.f};
  c.ortho_half_height = half_height;
  c.from_file = true;
  return c;
}

TEST(OrthographicCamera, ParallelRaysFromTheEyePlane) {
  const int w = 40, h = 20;
  std::vector<uint32_t> order(w * h);
  std::iota(order.begin(), order.end(), 0u);
  const PixelRays r = make_primary_rays(ortho({0.f, 0.f, 5.f}, {0.f, 0.f, 0.f}, 2.f), w, h, order, 1, 0, false);
  for (const Ray& ray : r.rays) {
    EXPECT_EQ(ray.dir.x, 0.f);
    EXPECT_EQ(ray.dir.y, 0.f);
    EXPECT_EQ(ray.dir.z, -1.f);
    EXPECT_EQ(ray.org.z, 5.f);
  }
  // Pixel centres: x = (2 (i + 0.5) / w - 1) h aspect, y = (1 - 2 (j + 0.5) / h) h, aspect 2.
  EXPECT_NEAR(r.rays[0].org.x, -0.975f * 4.f, 1e-6f);
  EXPECT_NEAR(r.rays[0].org.y, 0.95f * 2.f, 1e-6f);
  EXPECT_NEAR(r.rays[w * h - 1].org.x, 0.975f * 4.f, 1e-6f);
  EXPECT_NEAR(r.rays[w * h - 1].org.y, -0.95f * 2.f, 1e-6f);
}

// A floor quad of half-size e at y = 0 under a directional light, seen from above.
Scene floor_scene(float e) {
  Scene s;
  s.name = "floor";
  s.source = "test";
  Material m;
  m.base_color = Vec3(0.5f);
  s.materials = {m};
  s.positions = {{-e, 0.f, -e}, {e, 0.f, -e}, {e, 0.f, e}, {-e, 0.f, e}};
  s.normals.assign(4, Vec3{0.f, 1.f, 0.f});
  s.indices = {0, 2, 1, 0, 3, 2};
  s.tri_material = {0, 0};
  PunctualLight sun;
  sun.type = LightType::Directional;
  sun.direction = {0.f, -1.f, 0.f};
  sun.intensity = Vec3(2.f);
  s.lights = {sun};
  // Straight down (up = -z), covering half the floor.
  s.camera = ortho({0.f, 3.f * e, 0.f}, {0.f, 0.f, 0.f}, 0.5f * e);
  s.camera.up = {0.f, 0.f, -1.f};
  return s;
}

TEST(OrthographicCamera, FloorUnderADirectionalLightIsUniformAndSurvivesRebasing) {
  for (float e : {1.f, 1.f / 256.f}) {  // the second scene is rebased x 128: the view must scale with it
    Scene s = floor_scene(e);
    finalize_scene(s);
    ASSERT_TRUE(s.camera.from_file);
    EXPECT_EQ(s.camera.ortho_half_height, 0.5f * e * s.rebase_scale);
    const Bvh bvh = build_bvh(s);
    auto tracer = make_tracer(parse_plugin_spec("cpu"), s, bvh);
    auto gen = make_generator(parse_plugin_spec("noopt"));
    RenderSettings rs = test::small(16, 12);
    rs.max_depth = 1;
    PathTracer pt(s, *tracer, *gen, rs);
    Accumulator acc(rs.width, rs.height);
    pt.render_frames(0, 1, acc);
    const Image img = acc.mean();
    // Every pixel sees the floor (the view is 0.5 e x 0.67 e of a 2 e floor): L = albedo / pi x E.
    for (size_t p = 0; p < img.pixels(); ++p) EXPECT_NEAR(img.at(p).y, 0.5f / 3.14159265f * 2.f, 1e-5f) << p;
  }
}

}  // namespace
}  // namespace raycoh
