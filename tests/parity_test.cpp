// Parity of our traversal (tracer `cpu`) with Embree (tracer `embree`, every mode), the correctness oracle
// (docs/design.md section 4): on the built-in scenes and every shared scene, primary rays from the scene camera and
// cosine-distributed diffuse rays from their hits must agree on hit/miss, and hits on primitive id or, for
// ties (shared edges, coplanar duplicates), on t. Also: rejected and axis-aligned rays, thread-count
// determinism, and the registry's errors.
//
// Tolerances: t within 1e-4 * max(1, t). Embree's default triangle test is not watertight, so a ray through a
// shared edge or vertex can slip through in Embree and not in ours (whose test is watertight); such rays show up
// as hit/miss disagreements or as a different primitive further away. Both are counted per scene and allowed up
// to kMaxLeakFraction of the rays.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "tests/test_util.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

constexpr int kWidth = 128, kHeight = 96;
constexpr uint32_t kSeed = 0x5eed;
constexpr float kRelTolerance = 1e-4f;
constexpr double kMaxLeakFraction = 1e-4;

const std::vector<std::string> kEmbreeModes = {"single", "packet16", "stream_coherent", "stream_incoherent"};

// Pinhole camera rays through the pixel centres, scanline order, y = 0 at the top.
std::vector<Ray> camera_rays(const Camera& cam, int width, int height) {
  const Vec3 forward = normalize(cam.target - cam.eye);
  const Vec3 right = normalize(cross(forward, cam.up));
  const Vec3 up = cross(right, forward);
  const float tan_half = std::tan(cam.vfov_deg * 0.5f * kPi / 180.f);
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  std::vector<Ray> rays;
  rays.reserve(size_t(width) * height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const float sx = (2.f * (x + 0.5f) / width - 1.f) * tan_half * aspect;
      const float sy = (1.f - 2.f * (y + 0.5f) / height) * tan_half;
      rays.push_back(Ray{cam.eye, 0.f, normalize(forward + right * sx + up * sy), __builtin_huge_valf()});
    }
  }
  return rays;
}

// One cosine-distributed diffuse ray per primary hit, leaving on the side the primary ray came from.
std::vector<Ray> diffuse_rays(const Scene& scene, const std::vector<Ray>& primary, const std::vector<Hit>& hits) {
  std::vector<Ray> rays;
  for (size_t i = 0; i < primary.size(); ++i) {
    const Hit& h = hits[i];
    if (!h.valid()) continue;
    const Vec3 v0 = scene.positions[scene.indices[3 * size_t{h.prim}]];
    const Vec3 v1 = scene.positions[scene.indices[3 * size_t{h.prim} + 1]];
    const Vec3 v2 = scene.positions[scene.indices[3 * size_t{h.prim} + 2]];
    Vec3 ng = normalize(cross(v1 - v0, v2 - v0));
    if (dot(ng, primary[i].dir) > 0.f) ng = -ng;
    const Vec3 p = v0 * (1.f - h.u - h.v) + v1 * h.u + v2 * h.v;
    const auto pixel = static_cast<uint32_t>(i);
    const Vec3 local = sample_cosine_hemisphere(rng_float(kSeed, 0, pixel, kDimSecondary0),
                                                rng_float(kSeed, 0, pixel, kDimSecondary1));
    rays.push_back(
        Ray{offset_ray_origin(p, ng), 0.f, normalize(make_frame(ng).to_world(local)), __builtin_huge_valf()});
  }
  return rays;
}

std::vector<Hit> trace(Tracer& tracer, const std::vector<Ray>& rays) {
  std::vector<Hit> hits(rays.size());
  tracer.trace(rays.data(), rays.size(), hits.data());
  return hits;
}

struct Parity {
  size_t rays = 0, hits = 0;
  size_t hit_miss = 0;       // one hits, the other misses
  size_t ties = 0;           // different primitives at the same t (shared edges, coplanar duplicates)
  size_t prim_mismatch = 0;  // different primitives at different t (a leak through an edge)
  size_t t_mismatch = 0;     // same primitive, t outside the tolerance
  float max_rel_dt = 0.f;    // over hits on the same primitive
  float max_duv = 0.f;       // over hits on the same primitive
  size_t leaks() const { return hit_miss + prim_mismatch; }
};

Parity compare(const std::vector<Hit>& ours, const std::vector<Hit>& oracle) {
  Parity p;
  p.rays = ours.size();
  for (size_t i = 0; i < ours.size(); ++i) {
    const Hit &a = ours[i], &b = oracle[i];
    if (a.valid() != b.valid()) {
      ++p.hit_miss;
      continue;
    }
    if (!a.valid()) continue;
    ++p.hits;
    const float scale = std::max(1.f, std::fabs(b.t));
    const float dt = std::fabs(a.t - b.t);
    if (a.prim != b.prim) {
      (dt <= kRelTolerance * scale ? p.ties : p.prim_mismatch) += 1;
      continue;
    }
    p.max_rel_dt = std::max(p.max_rel_dt, dt / scale);
    p.max_duv = std::max({p.max_duv, std::fabs(a.u - b.u), std::fabs(a.v - b.v)});
    p.t_mismatch += dt > kRelTolerance * scale;
  }
  return p;
}

void report(const std::string& scene, const char* kind, const std::string& tracer, const Parity& p) {
  std::printf(
      "[parity] %-22s %-8s %-31s rays %6zu hits %6zu hit/miss %3zu prim-mismatch %3zu ties %3zu "
      "t-mismatch %zu max|dt|/t %.1e max|duv| %.1e\n",
      scene.c_str(), kind, tracer.c_str(), p.rays, p.hits, p.hit_miss, p.prim_mismatch, p.ties, p.t_mismatch,
      static_cast<double>(p.max_rel_dt), static_cast<double>(p.max_duv));
}

void expect_parity(const Parity& p) {
  EXPECT_EQ(p.t_mismatch, 0u);
  EXPECT_LE(static_cast<double>(p.leaks()), kMaxLeakFraction * static_cast<double>(p.rays))
      << p.hit_miss << " hit/miss disagreements and " << p.prim_mismatch << " primitive mismatches in " << p.rays
      << " rays";
}

std::vector<std::string> parity_scenes() {
  std::vector<std::string> specs = {"cornell", "voxels"};
  for (const auto& file : test::shared_scene_files()) specs.push_back(file.string());
  return specs;
}

class SceneParity : public ::testing::TestWithParam<std::string> {};

TEST_P(SceneParity, CpuMatchesEmbree) {
  const Scene scene = load_scene(GetParam());
  const Bvh bvh = build_bvh(scene);
  auto cpu = make_tracer(parse_plugin_spec("cpu"), scene, bvh);
  const std::vector<Ray> primary = camera_rays(scene.camera, kWidth, kHeight);
  const std::vector<Hit> primary_ours = trace(*cpu, primary);
  const std::vector<Ray> diffuse = diffuse_rays(scene, primary, primary_ours);
  const std::vector<Hit> diffuse_ours = trace(*cpu, diffuse);
  ASSERT_GT(diffuse.size(), 0u) << "the camera sees nothing";

  Parity total;
  for (const std::string& mode : kEmbreeModes) {
    const std::string spec = "embree:mode=" + mode;
    SCOPED_TRACE(spec);
    auto embree = make_tracer(parse_plugin_spec(spec), scene, bvh);
    const Parity p1 = compare(primary_ours, trace(*embree, primary));
    const Parity p2 = compare(diffuse_ours, trace(*embree, diffuse));
    report(scene.name, "primary", spec, p1);
    report(scene.name, "diffuse", spec, p2);
    expect_parity(p1);
    expect_parity(p2);
    total.rays += p1.rays + p2.rays;
    total.hit_miss += p1.hit_miss + p2.hit_miss;
    total.prim_mismatch += p1.prim_mismatch + p2.prim_mismatch;
    total.ties += p1.ties + p2.ties;
  }
  RecordProperty("rays", std::to_string(total.rays));
  RecordProperty("hit_miss", std::to_string(total.hit_miss));
  RecordProperty("prim_mismatch", std::to_string(total.prim_mismatch));
  RecordProperty("ties", std::to_string(total.ties));
}

std::string scene_test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string stem = std::filesystem::path(info.param).stem().string();
  for (char& c : stem)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return stem;
}

INSTANTIATE_TEST_SUITE_P(Scenes, SceneParity, ::testing::ValuesIn(parity_scenes()), scene_test_name);

TEST(Parity, SharedScenesPresent) {
  if (test::shared_scene_files().empty()) GTEST_SKIP() << "no shared scenes found (set RAYCOH_SCENES)";
}

// A small closed box of two-triangle walls, built by hand so that this test needs no scene loader.
Scene box_scene() {
  Scene s;
  s.name = "box";
  const Vec3 c[8] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
  s.positions.assign(c, c + 8);
  s.normals.assign(8, Vec3{0.f, 0.f, 1.f});
  s.indices = {0, 1, 3, 0, 3, 2, 4, 7, 5, 4, 6, 7, 0, 4, 5, 0, 5, 1,
               2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7, 1, 7, 3};
  s.tri_material.assign(12, 0);
  s.materials.push_back(Material{});
  for (const Vec3& p : s.positions) s.bounds.grow(p);
  s.camera.eye = {0.5f, 0.5f, 0.5f};
  s.camera.target = {0.5f, 0.5f, 0.f};
  return s;
}

std::vector<std::unique_ptr<Tracer>> all_tracers(const Scene& scene, const Bvh& bvh) {
  std::vector<std::unique_ptr<Tracer>> tracers;
  tracers.push_back(make_tracer(parse_plugin_spec("cpu"), scene, bvh));
  for (const std::string& mode : kEmbreeModes)
    tracers.push_back(make_tracer(parse_plugin_spec("embree:mode=" + mode), scene, bvh));
  return tracers;
}

TEST(Parity, RejectedRaysMissInEveryTracer) {
  const Scene scene = box_scene();
  const Bvh bvh = build_bvh(scene);
  const float inf = __builtin_huge_valf(), nan = std::nanf("");
  const Vec3 o{0.5f, 0.5f, 0.5f}, d{0.f, 0.f, 1.f};
  // 37 rays, so that packets and streams have a partial tail.
  std::vector<Ray> rays;
  for (int i = 0; i < 4; ++i) {
    rays.push_back(Ray{o, 0.f, d, 0.f});          // tmax == tmin
    rays.push_back(Ray{o, 1.f, d, 0.5f});         // tmax < tmin
    rays.push_back(Ray{o, 0.f, Vec3{0.f}, inf});  // zero direction
    rays.push_back(Ray{{nan, 0.5f, 0.5f}, 0.f, d, inf});
    rays.push_back(Ray{o, 0.f, {inf, 0.f, 0.f}, inf});
    rays.push_back(Ray{o, nan, d, inf});
    rays.push_back(Ray{o, 0.f, d, nan});
    rays.push_back(Ray{o, 0.f, d, 0.25f});  // valid, but stops short of the wall
    rays.push_back(Ray{o, 0.f, d, inf});    // valid, hits the top wall at t = 0.5
  }
  rays.push_back(Ray{o, 0.f, {0.f, -1.f, 0.f}, inf});
  for (auto& tracer : all_tracers(scene, bvh)) {
    SCOPED_TRACE(tracer->params());
    const std::vector<Hit> hits = trace(*tracer, rays);
    for (size_t i = 0; i < rays.size(); ++i) {
      const bool should_hit = i == rays.size() - 1 || i % 9 == 8;
      ASSERT_EQ(hits[i].valid(), should_hit) << "ray " << i;
      if (should_hit) {
        EXPECT_FLOAT_EQ(hits[i].t, 0.5f) << "ray " << i;
      } else {
        // A miss reports t = tmax, like closest_hit().
        EXPECT_EQ(std::memcmp(&hits[i].t, &rays[i].tmax, sizeof(float)), 0) << "ray " << i;
      }
    }
  }
}

TEST(Parity, AxisAlignedRaysAndZeroComponents) {
  const Scene scene = box_scene();
  const Bvh bvh = build_bvh(scene);
  std::vector<Ray> rays;
  const float inf = __builtin_huge_valf();
  for (const Vec3 d : {Vec3{1, 0, 0}, Vec3{-1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, -1, 0}, Vec3{0, 0, 1}, Vec3{0, 0, -1},
                       Vec3{-0.f, 0.6f, 0.8f}, Vec3{0.6f, -0.f, -0.8f}})
    for (float x : {0.1f, 0.37f, 0.5f, 0.9f}) rays.push_back(Ray{{x, 0.3f, 0.6f}, 0.f, d, inf});
  std::vector<std::vector<Hit>> results;
  for (auto& tracer : all_tracers(scene, bvh)) results.push_back(trace(*tracer, rays));
  for (size_t i = 0; i < rays.size(); ++i) {
    ASSERT_TRUE(results[0][i].valid()) << "ray " << i << " escaped the closed box";
    for (size_t k = 1; k < results.size(); ++k) {
      EXPECT_TRUE(results[k][i].valid()) << "tracer " << k << " ray " << i;
      EXPECT_NEAR(results[k][i].t, results[0][i].t, 1e-5f) << "tracer " << k << " ray " << i;
    }
  }
}

TEST(Parity, BarycentricsFollowTheSharedConvention) {
  Scene scene = box_scene();
  const Bvh bvh = build_bvh(scene);
  const Ray ray{{0.7f, 0.2f, 0.5f}, 0.f, {0.f, 0.f, -1.f}, __builtin_huge_valf()};
  for (auto& tracer : all_tracers(scene, bvh)) {
    SCOPED_TRACE(tracer->params());
    Hit h;
    tracer->trace(&ray, 1, &h);
    ASSERT_TRUE(h.valid());
    const Vec3 v0 = scene.positions[scene.indices[3 * h.prim]], v1 = scene.positions[scene.indices[3 * h.prim + 1]],
               v2 = scene.positions[scene.indices[3 * h.prim + 2]];
    const Vec3 p = v0 * (1.f - h.u - h.v) + v1 * h.u + v2 * h.v;
    EXPECT_NEAR(p.x, 0.7f, 1e-6f);
    EXPECT_NEAR(p.y, 0.2f, 1e-6f);
    EXPECT_NEAR(p.z, 0.f, 1e-6f);
  }
}

TEST(Parity, CpuTracerIsDeterministicAcrossThreadCounts) {
  const Scene scene = load_scene("voxels");
  const Bvh bvh = build_bvh(scene);
  auto cpu = make_tracer(parse_plugin_spec("cpu"), scene, bvh);
  const std::vector<Ray> primary = camera_rays(scene.camera, kWidth, kHeight);
  const std::vector<Ray> diffuse = diffuse_rays(scene, primary, trace(*cpu, primary));
  auto trace_with = [&](size_t threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return trace(*cpu, diffuse);
  };
  const std::vector<Hit> one = trace_with(1), two = trace_with(2);
  EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(Hit)), 0);
}

std::string error_of(const std::string& spec, const Scene& scene, const Bvh& bvh) {
  try {
    make_tracer(parse_plugin_spec(spec), scene, bvh);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(TracerRegistry, NamesParametersAndErrors) {
  const Scene scene = box_scene();
  const Bvh bvh = build_bvh(scene);
#if defined(RAYCOH_HAVE_CUDA)
  ASSERT_EQ(tracer_infos().size(), 4u);  // + cuda
  EXPECT_EQ(tracer_infos()[3].name, "cuda");
  const std::string valid = "cpu, embree, simt, cuda";
#else
  ASSERT_EQ(tracer_infos().size(), 3u);
  const std::string valid = "cpu, embree, simt";
#endif
  EXPECT_EQ(tracer_infos()[0].name, "cpu");
  EXPECT_EQ(tracer_infos()[1].name, "embree");
  EXPECT_EQ(tracer_infos()[2].name, "simt");
  EXPECT_EQ(make_tracer(parse_plugin_spec("cpu"), scene, bvh)->params(), "bvh=bvh2");
  EXPECT_EQ(make_tracer(parse_plugin_spec("cpu:bvh=cwbvh"), scene, bvh)->params(), "bvh=cwbvh");
  EXPECT_EQ(make_tracer(parse_plugin_spec("embree"), scene, bvh)->params(), "mode=single,quality=high");
  EXPECT_EQ(make_tracer(parse_plugin_spec("embree:quality=medium,mode=packet16"), scene, bvh)->params(),
            "mode=packet16,quality=medium");

  EXPECT_EQ(error_of("optix", scene, bvh), "unknown tracer 'optix'; valid tracers: " + valid);
  const std::string bad_mode = error_of("embree:mode=packet8", scene, bvh);
  EXPECT_NE(bad_mode.find("tracer 'embree'"), std::string::npos) << bad_mode;
  EXPECT_NE(bad_mode.find("stream_incoherent"), std::string::npos) << bad_mode;
  const std::string bad_key = error_of("embree:modes=single", scene, bvh);
  EXPECT_NE(bad_key.find("unknown parameter 'modes'"), std::string::npos) << bad_key;
  EXPECT_NE(bad_key.find("mode, quality"), std::string::npos) << bad_key;
  const std::string cpu_key = error_of("cpu:threads=2", scene, bvh);
  EXPECT_NE(cpu_key.find("tracer 'cpu'"), std::string::npos) << cpu_key;
}

}  // namespace
}  // namespace raycoh
