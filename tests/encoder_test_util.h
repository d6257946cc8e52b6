// Helpers shared by the encoder tests (keys_test, encoder_registry_test, mlhcc_test, reorder_test): ray batches
// (hand-made or random), the keys an encoder spec gives through make_encoder, the unit box, and a hand-built
// four-leaf BVH for MLHCC.
#pragma once

#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "encoders/encoder.h"

namespace raycoh::test {

inline constexpr float kInf = std::numeric_limits<float>::infinity();
inline constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

inline RayBatch make_batch(const std::vector<Ray>& rays) {
  RayBatch b;
  b.width = static_cast<int>(rays.size());
  b.height = 1;
  b.resize(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    b.rays[i] = rays[i];
    b.pixel[i] = static_cast<uint32_t>(i);
    b.pdf[i] = static_cast<float>(i) + 0.5f;
  }
  return b;
}

inline Ray ray(Vec3 o, Vec3 d, float tmax = kInf) { return Ray{o, 0.f, d, tmax}; }

inline Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<float> n(0.f, 1.f);
  for (;;) {
    const Vec3 v{n(rng), n(rng), n(rng)};
    if (dot(v, v) > 1e-6f) return normalize(v);
  }
}

inline std::vector<Ray> random_rays(const Bounds& box, size_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  std::vector<Ray> rays;
  for (size_t i = 0; i < count; ++i) {
    const Vec3 o{box.lo.x + u(rng) * (box.hi.x - box.lo.x), box.lo.y + u(rng) * (box.hi.y - box.lo.y),
                 box.lo.z + u(rng) * (box.hi.z - box.lo.z)};
    const float tmax = i % 3 == 0 ? kInf : u(rng) * 2.f;
    rays.push_back(ray(o, random_unit(rng), tmax));
  }
  return rays;
}

inline std::vector<uint64_t> keys_of(const std::string& spec, const EncoderContext& ctx, const RayBatch& batch) {
  auto encoder = make_encoder(parse_plugin_spec(spec), ctx);
  std::vector<uint64_t> keys(batch.size(), 0xDEADBEEFull);
  encoder->encode(batch, keys.data());
  return keys;
}

inline Bounds box_of(Vec3 lo, Vec3 hi) { return Bounds{lo, hi}; }
inline const Bounds kUnitBox = box_of({0.f, 0.f, 0.f}, {1.f, 1.f, 1.f});

// Root over x in [0,1]: node 1 = [0,.5], node 2 = [.5,1], each with two leaves of width .25 (y, z in [0,1]).
// Surface areas (half): root 3, nodes 2, leaves 1.5.
inline Bvh tiny_bvh() {
  auto node = [](Vec3 lo0, Vec3 hi0, Vec3 lo1, Vec3 hi1, int32_t c0, int32_t c1) {
    BvhNode n{};
    n.lo0 = lo0;
    n.hi0 = hi0;
    n.lo1 = lo1;
    n.hi1 = hi1;
    n.child[0] = c0;
    n.child[1] = c1;
    return n;
  };
  Bvh bvh;
  bvh.nodes.push_back(node({0, 0, 0}, {0.5f, 1, 1}, {0.5f, 0, 0}, {1, 1, 1}, 1, 2));
  bvh.nodes.push_back(
      node({0, 0, 0}, {0.25f, 1, 1}, {0.25f, 0, 0}, {0.5f, 1, 1}, make_leaf_ref(0, 1), make_leaf_ref(1, 1)));
  bvh.nodes.push_back(
      node({0.5f, 0, 0}, {0.75f, 1, 1}, {0.75f, 0, 0}, {1, 1, 1}, make_leaf_ref(2, 1), make_leaf_ref(3, 1)));
  bvh.bounds = kUnitBox;
  return bvh;
}

}  // namespace raycoh::test
