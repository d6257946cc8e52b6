// The alpha MASK test scene of alpha_mask_test and gpu_alpha_test: a glTF card whose texture is transparent on
// its left half, in front of a wall, and rays through both halves.
#pragma once

#include <fmt/format.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/ray.h"
#include "tests/scenes_test_util.h"

namespace raycoh::test {

// 4 x 1 RGBA PNG: texels 0 and 1 red with alpha 0, texels 2 and 3 green with alpha 255. Bilinear alpha crosses
// 0.5 at u = 0.5.
inline const std::vector<uint8_t> kHalfCutPng = {
    137, 80, 78, 71, 13,  10,  26, 10,  0,   0, 0,   13, 73, 72, 68, 82, 0,   0,   0,  4,   0,   0,   0,   1,  8,
    6,   0,  0,  0,  249, 60,  15, 205, 0,   0, 0,   17, 73, 68, 65, 84, 120, 218, 99, 248, 207, 192, 192, 0,  194,
    64,  2,  12, 1,  43,  229, 5,  251, 188, 8, 204, 4,  0,  0,  0,  0,  73,  69,  78, 68,  174, 66,  96,  130};

// The card: x, y in [0, 1] at z = 0 with u = x, v = y, material 0; the wall at z = -1, material 1. Material 0 is
// `card_material` (JSON), using texture 0 = kHalfCutPng.
// Written under temp_dir(dir) (one dir per test program: ctest may run them at once).
inline std::filesystem::path write_card(const std::string& dir, const std::string& name,
                                        const std::string& card_material) {
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
  return w.write(dir, name);
}

inline constexpr const char* kMaskCard =
    R"({"name":"card","alphaMode":"MASK","pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})";

// Rays along -z from z = 1 at x = 0.05, 0.15, ..., 0.95 (y = 0.5): the first five through the cut-out.
inline std::vector<Ray> rays_through_card() {
  std::vector<Ray> rays;
  for (int i = 0; i < 10; ++i) rays.push_back(Ray{{0.05f + 0.1f * i, 0.5f, 1.f}, 0.f, {0.f, 0.f, -1.f}, 10.f});
  return rays;
}

}  // namespace raycoh::test
