// The stiff-case catalogue of `raycoh stability` (docs/stability.md): built-in scenes made to stress the
// traversal's arithmetic (far, scaled, slivers, coplanar, flat, grazing, pile), each described beside its factory.
// Registered with the other built-ins in scenes/procedural.cpp.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/params.h"
#include "core/rng.h"
#include "scenes/procedural_parts.h"
#include "scenes/scene.h"

namespace raycoh::procedural {

void set_camera(Scene& s, Vec3 eye, Vec3 target, float vfov_deg) {
  s.camera.eye = eye;
  s.camera.target = target;
  s.camera.up = {0.f, 1.f, 0.f};
  s.camera.vfov_deg = vfov_deg;
  s.camera.from_file = true;
}

// voxels content with its camera on integer coordinates: moved by an integer offset (below 2^24 minus the
// content's extent) every vertex and the eye stay exact, so only the rays' arithmetic changes.
// The camera is nearer than voxels' own so that small sizes fill the image.
Scene integer_voxels(int size) {
  Scene s = make_voxels(size);
  const float half = 0.5f * static_cast<float>(size);
  const Vec3 centre{half, static_cast<float>(kVoxelWaterLevel), half};
  const Vec3 eye = centre + normalize(Vec3{-1.f, 0.75f, -1.f}) * (2.2f * half + 16.f);
  auto round3 = [](Vec3 v) { return Vec3{std::round(v.x), std::round(v.y), std::round(v.z)}; };
  set_camera(s, round3(eye), round3(centre), s.camera.vfov_deg);
  return s;
}

void transform(Scene& s, float scale, Vec3 offset) {
  for (Vec3& p : s.positions) p = p * scale + offset;
  set_camera(s, s.camera.eye * scale + offset, s.camera.target * scale + offset, s.camera.vfov_deg);
}

const ParamTable& far_params() {
  static const ParamTable table = {float_param("offset", 1e7f, 0.f, 1e9f, "added to every coordinate (x, y and z)"),
                                   int_param("size", 16, 4, 256, "voxels columns along x and z")};
  return table;
}

Scene make_far_scene(ParamSet& params) {
  const float offset = params.get_float("offset");
  const int size = params.get_int("size");
  params.finish();
  Scene s = integer_voxels(size);
  transform(s, 1.f, Vec3(offset));
  return s;
}

const ParamTable& scaled_params() {
  static const ParamTable table = {float_param("scale", 1e-4f, 1e-8f, 1e8f, "factor on every coordinate"),
                                   int_param("size", 16, 4, 256, "voxels columns along x and z")};
  return table;
}

Scene make_scaled_scene(ParamSet& params) {
  const float scale = params.get_float("scale");
  const int size = params.get_int("size");
  params.finish();
  Scene s = integer_voxels(size);
  transform(s, scale, Vec3(0.f));
  return s;
}

const ParamTable& slivers_params() {
  static const ParamTable table = {
      float_param("aspect", 1e6f, 4.f, 1e8f, "long edge / short edge of the needles, and of the slivers' height")};
  return table;
}

Scene make_slivers_scene(ParamSet& params) {
  const float aspect = params.get_float("aspect");
  params.finish();
  return make_cornell(aspect);
}

// Every quad of cornell twice, exactly coplanar, the twin split along the other diagonal and given the next
// (non-emissive) material; and one more floor, coplanar with it and shifted half its width in the plane.
Scene make_coplanar_scene(ParamSet& params) {
  params.finish();
  Scene s = make_cornell();
  const size_t quads = s.positions.size() / 4;
  const uint32_t light = static_cast<uint32_t>(s.materials.size() - 1);
  for (size_t q = 0; q < quads; ++q) {
    const uint32_t src = static_cast<uint32_t>(4 * q), base = static_cast<uint32_t>(s.positions.size());
    for (uint32_t k = 0; k < 4; ++k) {
      s.positions.push_back(s.positions[src + k]);
      s.normals.push_back(s.normals[src + k]);
    }
    s.indices.insert(s.indices.end(), {base + 1, base + 2, base + 3, base + 1, base + 3, base});
    const uint32_t m = s.tri_material[2 * q];
    s.tri_material.insert(s.tri_material.end(), 2, m == light ? light : (m + 1) % light);
  }
  QuadBuilder b{s};
  b.quad({-0.5f, 0.f, 1.f}, {1.f, 0.f, 1.f}, {1.f, 0.f, -0.5f}, {-0.5f, 0.f, -0.5f}, {0.f, 1.f, 0.f}, 4);
  return s;
}

// Materials of the catalogue's plain scenes: diffuse white and red, glossy metal.
void plain_materials(Scene& s) {
  s.materials = {make_material("white", {0.75f, 0.75f, 0.75f}, 1.f), make_material("red", {0.6f, 0.1f, 0.08f}, 1.f),
                 make_material("metal", {0.9f, 0.9f, 0.9f}, 0.2f, 1.f)};
}

const ParamTable& flat_params() {
  static const ParamTable table = {int_param("size", 16, 1, 1024, "unit quads along x and z")};
  return table;
}

// A size x size grid of unit quads in the plane y = 0 (zero extent in y), hashed materials, seen from above.
Scene make_flat_scene(ParamSet& params) {
  const int size = params.get_int("size");
  params.finish();
  Scene s;
  plain_materials(s);
  QuadBuilder b{s};
  for (int z = 0; z < size; ++z)
    for (int x = 0; x < size; ++x) {
      const float x0 = static_cast<float>(x), z0 = static_cast<float>(z);
      const uint32_t m = static_cast<uint32_t>(hash01(static_cast<uint32_t>(x), static_cast<uint32_t>(z), 7u) * 3.f);
      b.quad({x0, 0.f, z0}, {x0 + 1.f, 0.f, z0}, {x0 + 1.f, 0.f, z0 + 1.f}, {x0, 0.f, z0 + 1.f}, {0.f, 1.f, 0.f},
             std::min(m, 2u));
    }
  const float n = static_cast<float>(size);
  set_camera(s, {0.5f * n, 0.8f * n, -0.4f * n}, {0.5f * n, 0.f, 0.5f * n}, 50.f);
  return s;
}

const ParamTable& grazing_params() {
  static const ParamTable table = {float_param("height", 1e-3f, 1e-6f, 10.f, "camera height over the ground")};
  return table;
}

// A 512 x 512 ground of 16-unit quads seen from `height` above it towards the horizon, and eight thin walls
// running along the view (seen edge-on): primary hits at grazing angles, secondary rays leaving near the plane.
Scene make_grazing_scene(ParamSet& params) {
  const float height = params.get_float("height");
  params.finish();
  Scene s;
  plain_materials(s);
  QuadBuilder b{s};
  for (int z = 0; z < 32; ++z)
    for (int x = 0; x < 32; ++x) {
      const float x0 = 16.f * static_cast<float>(x), z0 = 16.f * static_cast<float>(z);
      b.quad({x0, 0.f, z0}, {x0 + 16.f, 0.f, z0}, {x0 + 16.f, 0.f, z0 + 16.f}, {x0, 0.f, z0 + 16.f}, {0.f, 1.f, 0.f},
             static_cast<uint32_t>((x + z) % 3));
    }
  for (int w = 0; w < 8; ++w) {
    const float x = 256.f + (static_cast<float>(w) - 3.5f) * 6.f;
    b.quad({x, 0.f, 8.f}, {x, 0.f, 504.f}, {x, 4.f, 504.f}, {x, 4.f, 8.f}, {w < 4 ? 1.f : -1.f, 0.f, 0.f}, 1u);
  }
  set_camera(s, {256.5f, height, 0.f}, {256.5f, 0.f, 512.f}, 40.f);
  return s;
}

const ParamTable& pile_params() {
  static const ParamTable table = {
      int_param("tris", 4096, 1, 2000000, "triangles, all over the same unit square (the BVH cannot separate them)"),
      float_param("spread", 1e-6f, 0.f, 1.f, "largest lift and tilt of a triangle")};
  return table;
}

// `tris` large triangles covering the unit square, each tilted and lifted by hashed amounts up to `spread`: they
// cross each other everywhere, every ray visits every leaf, and the closest hit is decided among distances
// that differ by about float precision.
Scene make_pile_scene(ParamSet& params) {
  const int tris = params.get_int("tris");
  const float spread = params.get_float("spread");
  params.finish();
  Scene s;
  plain_materials(s);
  for (int i = 0; i < tris; ++i) {
    const uint32_t u = static_cast<uint32_t>(i);
    const float a = spread * (hash01(u, 1u, 11u) - 0.5f), c = spread * (hash01(u, 2u, 11u) - 0.5f);
    const float h = spread * hash01(u, 3u, 11u);
    auto at = [&](float x, float z) { return Vec3{x, h + a * x + c * z, z}; };
    const uint32_t base = static_cast<uint32_t>(s.positions.size());
    for (const Vec3& p : {at(-1.f, -1.f), at(-1.f, 3.f), at(3.f, -1.f)}) {
      s.positions.push_back(p);
      s.normals.push_back({0.f, 1.f, 0.f});
    }
    s.indices.insert(s.indices.end(), {base, base + 1, base + 2});
    s.tri_material.push_back(u % 3);
  }
  set_camera(s, {0.5f, 2.f, 0.5f}, {0.5f, 0.f, 0.5f}, 30.f);
  s.camera.up = {0.f, 0.f, 1.f};
  return s;
}

}  // namespace raycoh::procedural
