// Built-in procedural scenes, so that the harness runs with no download. All are pure functions of their
// parameters (hashed noise, no RNG state): two builds are bit-identical.
//
// cornell   The Cornell box in the McGuire archive's proportions (x in [-1, 1], y in [0, 2], z in [-1, 1],
//           open towards +z; block footprints from CornellBox-Original.obj): white floor, ceiling and back
//           wall, red left and green right wall (diffuse), a glossy metal tall block (roughness 0.2), a diffuse
//           short block and an emissive quad under the ceiling (radiance (17, 12, 4)). 32 triangles.
//           Camera at (0, 1, 3.5) looking in, vertical field of view 45 degrees. No parameters.
//
// voxels    A Minecraft-like landscape of unit cubes, a heightmap of size x size columns (heights 1..24 from
//           hashed value noise, 4 octaves from a 32-block wavelength) with water at level 10: specular water tops over
//           low columns, diffuse grass, dirt, stone, sand and snow blocks, and a few glossy blocks (gold ore, quartz)
//           in the stone. Only faces not shared with a neighbouring block are emitted (the world's underside is not: it
//           is never seen from above). Lit by sky + sun (no emitters); camera looking over the landscape from a corner.
//           Parameters: voxels_params() below (about 5 size^2 triangles).
//
// far, scaled, slivers, coplanar, flat, grazing, pile: the stiff-case catalogue of `raycoh stability`, each
// described beside its factory below and in docs/stability.md.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/params.h"
#include "core/rng.h"
#include "scenes/builtin_scenes.h"
#include "scenes/procedural_parts.h"
#include "scenes/scene.h"

namespace raycoh {

namespace procedural {

Material make_material(const char* name, Vec3 base, float roughness, float metallic, Vec3 emission) {
  Material m;
  m.name = name;
  m.base_color = base;
  m.roughness = roughness;
  m.metallic = metallic;
  m.emission = emission;
  m.cls = classify_material(m);
  return m;
}

Scene make_cornell(float aspect) {
  Scene s;
  enum : uint32_t { kWhite, kRed, kGreen, kShort, kTall, kLight };
  s.materials = {
      make_material("white", {0.725f, 0.71f, 0.68f}, 1.f),
      make_material("leftWall", {0.63f, 0.065f, 0.05f}, 1.f),
      make_material("rightWall", {0.14f, 0.45f, 0.091f}, 1.f),
      make_material("shortBox", {0.725f, 0.71f, 0.68f}, 1.f),
      make_material("tallBox", {0.91f, 0.92f, 0.92f}, 0.2f, 1.f),
      make_material("light", {0.78f, 0.78f, 0.78f}, 1.f, 0.f, {17.f, 12.f, 4.f}),
  };
  QuadBuilder b{s, aspect};
  const float x0 = -1.f, x1 = 1.f, y0 = 0.f, y1 = 2.f, z0 = -1.f, z1 = 1.f;
  b.quad({x0, y0, z1}, {x1, y0, z1}, {x1, y0, z0}, {x0, y0, z0}, {0.f, 1.f, 0.f}, kWhite);   // floor
  b.quad({x0, y1, z1}, {x0, y1, z0}, {x1, y1, z0}, {x1, y1, z1}, {0.f, -1.f, 0.f}, kWhite);  // ceiling
  b.quad({x0, y0, z0}, {x1, y0, z0}, {x1, y1, z0}, {x0, y1, z0}, {0.f, 0.f, 1.f}, kWhite);   // back wall
  b.quad({x0, y0, z1}, {x0, y0, z0}, {x0, y1, z0}, {x0, y1, z1}, {1.f, 0.f, 0.f}, kRed);     // left wall
  b.quad({x1, y0, z0}, {x1, y0, z1}, {x1, y1, z1}, {x1, y1, z0}, {-1.f, 0.f, 0.f}, kGreen);  // right wall
  const float short_box[4][2] = {{0.53f, 0.75f}, {0.70f, 0.17f}, {0.13f, 0.00f}, {-0.05f, 0.57f}};
  const float tall_box[4][2] = {{-0.53f, 0.09f}, {0.04f, -0.09f}, {-0.14f, -0.67f}, {-0.71f, -0.49f}};
  b.block(short_box, 0.6f, kShort);
  b.block(tall_box, 1.2f, kTall);
  // Just under the ceiling, so that it is not coplanar with it.
  b.quad({-0.24f, 1.98f, 0.16f}, {-0.24f, 1.98f, -0.22f}, {0.23f, 1.98f, -0.22f}, {0.23f, 1.98f, 0.16f},
         {0.f, -1.f, 0.f}, kLight);
  s.camera.eye = {0.f, 1.f, 3.5f};
  s.camera.target = {0.f, 1.f, 0.f};
  s.camera.up = {0.f, 1.f, 0.f};
  s.camera.vfov_deg = 45.f;
  s.camera.from_file = true;  // the scene's own view, not a default framing
  return s;
}

constexpr int kVoxelMaxHeight = 24;
constexpr int kVoxelSnowLine = 20;

float hash01(uint32_t a, uint32_t b, uint32_t c) {
  return static_cast<float>(hash32(a ^ hash32(b ^ hash32(c + 0x9e3779b9u))) >> 8) * (1.f / 16777216.f);
}

// Value noise: hashed lattice values, smoothstep-interpolated; wavelength in blocks.
float value_noise(float x, float z, float wavelength, uint32_t octave) {
  const float fx = x / wavelength, fz = z / wavelength;
  const float ix = std::floor(fx), iz = std::floor(fz);
  const float tx = fx - ix, tz = fz - iz;
  const float sx = tx * tx * (3.f - 2.f * tx), sz = tz * tz * (3.f - 2.f * tz);
  const uint32_t x0 = static_cast<uint32_t>(static_cast<int32_t>(ix)),
                 z0 = static_cast<uint32_t>(static_cast<int32_t>(iz));
  const float v00 = hash01(x0, z0, octave), v10 = hash01(x0 + 1, z0, octave);
  const float v01 = hash01(x0, z0 + 1, octave), v11 = hash01(x0 + 1, z0 + 1, octave);
  const float a = v00 + (v10 - v00) * sx, b = v01 + (v11 - v01) * sx;
  return a + (b - a) * sz;
}

int column_height(int x, int z) {
  float n = 0.f, total = 0.f, amp = 1.f, wavelength = 32.f;
  for (uint32_t o = 0; o < 4; ++o, amp *= 0.5f, wavelength *= 0.5f) {
    n += amp * value_noise(static_cast<float>(x) + 0.5f, static_cast<float>(z) + 0.5f, wavelength, o);
    total += amp;
  }
  n /= total;
  // Summed octaves cluster around 0.5; stretching the middle gives both lakes and peaks.
  n = std::clamp((n - 0.5f) * 2.2f + 0.5f, 0.f, 1.f);
  return 1 + std::min(kVoxelMaxHeight - 1, static_cast<int>(n * kVoxelMaxHeight));
}

enum VoxelMaterial : uint32_t { kGrass, kDirt, kStone, kSand, kSnow, kWater, kGold, kQuartz, kVoxelMaterialCount };

// Material of block y in a column of height h at (x, z).
uint32_t block_material(int x, int z, int y, int h) {
  const bool shore = h <= kVoxelWaterLevel + 1;
  if (y == h - 1) return shore ? kSand : (h >= kVoxelSnowLine ? kSnow : kGrass);
  if (y >= h - 4) return shore ? kSand : kDirt;
  const float r = hash01(static_cast<uint32_t>(x), static_cast<uint32_t>(z), static_cast<uint32_t>(y) + 1000u);
  if (r < 0.02f) return kGold;
  if (r < 0.04f) return kQuartz;
  return kStone;
}

Scene make_voxels(int size) {
  Scene s;
  s.materials.resize(kVoxelMaterialCount);
  s.materials[kGrass] = make_material("grass", {0.26f, 0.45f, 0.12f}, 1.f);
  s.materials[kDirt] = make_material("dirt", {0.42f, 0.29f, 0.18f}, 1.f);
  s.materials[kStone] = make_material("stone", {0.45f, 0.45f, 0.45f}, 1.f);
  s.materials[kSand] = make_material("sand", {0.76f, 0.70f, 0.50f}, 1.f);
  s.materials[kSnow] = make_material("snow", {0.90f, 0.92f, 0.95f}, 1.f);
  s.materials[kWater] = make_material("water", {0.05f, 0.15f, 0.25f}, 0.02f);
  s.materials[kGold] = make_material("gold_ore", {1.f, 0.78f, 0.34f}, 0.25f, 1.f);
  s.materials[kQuartz] = make_material("quartz", {0.92f, 0.9f, 0.88f}, 0.1f);

  const size_t n = static_cast<size_t>(size);
  std::vector<int> height(n * n);
  for (int z = 0; z < size; ++z)
    for (int x = 0; x < size; ++x) height[static_cast<size_t>(z) * n + static_cast<size_t>(x)] = column_height(x, z);
  auto h_at = [&](int x, int z) {
    return x < 0 || z < 0 || x >= size || z >= size ? 0 : height[static_cast<size_t>(z) * n + static_cast<size_t>(x)];
  };

  // About 3 quads per column on average (top, water or a side or two).
  s.positions.reserve(12 * n * n);
  s.normals.reserve(12 * n * n);
  s.indices.reserve(18 * n * n);
  s.tri_material.reserve(6 * n * n);
  QuadBuilder b{s};
  const int dx[4] = {1, -1, 0, 0}, dz[4] = {0, 0, 1, -1};
  for (int z = 0; z < size; ++z) {
    for (int x = 0; x < size; ++x) {
      const int h = h_at(x, z);
      const float x0 = static_cast<float>(x), x1 = x0 + 1.f, z0 = static_cast<float>(z), z1 = z0 + 1.f;
      const float top = static_cast<float>(h);
      b.quad({x0, top, z0}, {x1, top, z0}, {x1, top, z1}, {x0, top, z1}, {0.f, 1.f, 0.f},
             block_material(x, z, h - 1, h));
      if (h < kVoxelWaterLevel) {
        const float w = static_cast<float>(kVoxelWaterLevel);
        b.quad({x0, w, z0}, {x1, w, z0}, {x1, w, z1}, {x0, w, z1}, {0.f, 1.f, 0.f}, kWater);
      }
      for (int d = 0; d < 4; ++d) {
        const int hn = h_at(x + dx[d], z + dz[d]);
        // The face of block y towards the neighbour is exposed when the neighbour column is lower than y + 1.
        const float fx = dx[d] > 0 ? x1 : (dx[d] < 0 ? x0 : 0.f), fz = dz[d] > 0 ? z1 : (dz[d] < 0 ? z0 : 0.f);
        const Vec3 nrm{static_cast<float>(dx[d]), 0.f, static_cast<float>(dz[d])};
        for (int y = hn; y < h; ++y) {
          const float y0 = static_cast<float>(y), y1 = y0 + 1.f;
          const uint32_t m = block_material(x, z, y, h);
          if (dx[d] != 0) {
            b.quad({fx, y0, z0}, {fx, y0, z1}, {fx, y1, z1}, {fx, y1, z0}, nrm, m);
          } else {
            b.quad({x0, y0, fz}, {x1, y0, fz}, {x1, y1, fz}, {x0, y1, fz}, nrm, m);
          }
        }
      }
    }
  }

  const float half = 0.5f * static_cast<float>(size);
  const Vec3 centre{half, static_cast<float>(kVoxelWaterLevel), half};
  const float dist = 1.6f * half + 2.f * kVoxelMaxHeight;
  s.camera.eye = centre + normalize(Vec3{-1.f, 0.75f, -1.f}) * dist;
  s.camera.target = centre;
  s.camera.up = {0.f, 1.f, 0.f};
  s.camera.vfov_deg = 55.f;
  s.camera.from_file = true;  // the scene's own view, not a default framing
  // An afternoon sun, low enough for the hills to cast long shadows.
  s.env.sun_dir = normalize(Vec3{0.5f, 0.55f, 0.3f});
  return s;
}

}  // namespace procedural

namespace {

using namespace procedural;

const ParamTable& no_params() {
  static const ParamTable table;
  return table;
}

Scene make_cornell_scene(ParamSet& params) {
  params.finish();
  return make_cornell();
}

const ParamTable& voxels_params() {
  static const ParamTable table = {int_param("size", 64, 4, 1024, "columns along x and z")};
  return table;
}

Scene make_voxels_scene(ParamSet& params) {
  const int size = params.get_int("size");
  params.finish();
  return make_voxels(size);
}

[[noreturn]] void unknown_builtin(const std::string& name) {
  throw Error(fmt::format("scene '{}': no such built-in scene; built-ins: {}", name, join(builtin_scene_names())));
}

}  // namespace

const std::vector<SceneInfo>& builtin_scene_infos() {
  static const std::vector<SceneInfo> infos = {
      {"cornell",
       "Cornell box (McGuire proportions): red/green/white diffuse walls, glossy metal tall block, "
       "diffuse short block, emissive ceiling light; 32 triangles",
       no_params, make_cornell_scene},
      {"voxels",
       "voxel landscape of unit cubes (heightmap, water, grass/dirt/stone/sand/snow, a few glossy "
       "blocks), sky + sun lit",
       voxels_params, make_voxels_scene},
      // The stiff-case catalogue of `raycoh stability` (docs/stability.md).
      {"far", "voxels content (integer vertices and eye) moved by `offset` along x, y and z", far_params,
       make_far_scene},
      {"scaled", "voxels content (integer vertices and eye) scaled by `scale`", scaled_params, make_scaled_scene},
      {"slivers", "cornell with every quad split into five: a needle and a sliver of the given aspect, watertight",
       slivers_params, make_slivers_scene},
      {"coplanar", "cornell with every quad doubled, exactly coplanar, and a second floor overlapping the first",
       no_params, make_coplanar_scene},
      {"flat", "a grid of unit quads in y = 0: zero extent in y", flat_params, make_flat_scene},
      {"grazing", "a 512 x 512 ground and edge-on walls seen from just above the ground", grazing_params,
       make_grazing_scene},
      {"pile", "large triangles crossing over one square: one huge overlap the BVH cannot split", pile_params,
       make_pile_scene},
  };
  return infos;
}

std::vector<std::string> builtin_scene_names() {
  std::vector<std::string> names;
  for (const SceneInfo& info : builtin_scene_infos()) names.push_back(info.name);
  return names;
}

std::string builtin_scene_summary(const std::string& name) {
  for (const SceneInfo& info : builtin_scene_infos())
    if (info.name == name)
      return info.summary + (info.table().empty() ? "; no parameters" : "; params: " + info.params);
  unknown_builtin(name);
}

Scene make_builtin_scene(const std::string& spec) {
  const PluginSpec plugin = parse_plugin_spec(spec);
  const auto& infos = builtin_scene_infos();
  const auto it =
      std::find_if(infos.begin(), infos.end(), [&](const SceneInfo& info) { return info.name == plugin.name; });
  if (it == infos.end()) unknown_builtin(plugin.name);
  ParamSet params(fmt::format("scene '{}'", plugin.name), plugin.params, it->table());
  Scene scene = it->make(params);
  scene.name = plugin.name;
  scene.source = spec;
  finalize_scene(scene);
  return scene;
}

}  // namespace raycoh
