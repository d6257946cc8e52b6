// Every encoder through the registry (make_encoder): keys bit for bit against the reference for 32- and 64-bit
// keys, the documented bits per component of 32-bit keys, defined keys for NaN / Inf input, and the registry's
// names, parameters and errors.
#include <gtest/gtest.h>

#include <functional>
#include <set>
#include <string>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "encoders/encoder.h"
#include "encoders/keys.h"
#include "encoders/permute.h"
#include "tests/encoder_test_util.h"
#include "tests/key_reference.h"

namespace raycoh {
namespace {

using test::box_of;
using test::keys_of;
using test::kInf;
using test::kNaN;
using test::kUnitBox;
using test::make_batch;
using test::random_rays;
using test::ray;
using test::ref_aila;
using test::ref_costa;
using test::ref_origin;
using test::ref_reis;
using test::ref_twopoint;
using test::tiny_bvh;

// ---- every encoder against the reference, through make_encoder, 32- and 64-bit keys ------------------------

TEST(Encoders, KeysMatchTheBitByBitReference) {
  const Bounds box = box_of({-1.f, 0.f, -2.f}, {2.f, 3.f, -1.f});
  std::vector<Ray> rays = random_rays(box, 5000, 42);
  // Chosen rays: the box's corners and faces, the axis directions, tmax = 0.
  for (Vec3 d : {Vec3{1, 0, 0}, Vec3{-1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, -1, 0}, Vec3{0, 0, 1}, Vec3{0, 0, -1}}) {
    rays.push_back(ray(box.lo, d));
    rays.push_back(ray(box.hi, d));
    rays.push_back(ray(box.center(), d, 0.f));
    rays.push_back(ray({box.hi.x, 1.f, -1.5f}, d, 0.3f));
  }
  const RayBatch batch = make_batch(rays);
  const EncoderContext ctx{box, nullptr};
  struct Case {
    std::string spec;
    std::function<uint64_t(const Ray&)> ref;
  };
  const std::vector<Case> cases = {
      {"origin", [&](const Ray& r) { return ref_origin(r.org, box); }},
      {"reis", [&](const Ray& r) { return ref_reis(r.org, r.dir, box); }},
      {"costa", [&](const Ray& r) { return ref_costa(r.org, r.dir, box); }},
      {"aila", [&](const Ray& r) { return ref_aila(r.org, r.dir, box); }},
      {"twopoint", [&](const Ray& r) { return ref_twopoint(r.org, r.dir, r.tmax, box, 0.25f); }},
      {"twopoint:L=0.6", [&](const Ray& r) { return ref_twopoint(r.org, r.dir, r.tmax, box, 0.6f); }},
  };
  for (const Case& c : cases) {
    const std::string sep = c.spec.find(':') == std::string::npos ? ":" : ",";
    const std::vector<uint64_t> k64 = keys_of(c.spec + sep + "bits=64", ctx, batch);
    const std::vector<uint64_t> k32 = keys_of(c.spec, ctx, batch);  // 32 is the default
    for (size_t i = 0; i < rays.size(); ++i) {
      const uint64_t expected = c.ref(rays[i]);
      ASSERT_EQ(k64[i], expected) << c.spec << " ray " << i;
      ASSERT_EQ(k32[i], expected >> 32) << c.spec << " ray " << i;
    }
  }
}

TEST(Encoders, ThirtyTwoBitKeysHoldTheDocumentedBitsPerComponent) {
  // Origin: x 11, y 11, z 10 bits. Moving z by one 10-bit step changes the 32-bit key; a 2^-11 step does not.
  const EncoderContext ctx{kUnitBox, nullptr};
  const RayBatch batch = make_batch({ray({0, 0, 0}, {1, 0, 0}), ray({0, 0, 1.f / 1024}, {1, 0, 0}),
                                     ray({0, 0, 1.f / 2048}, {1, 0, 0}), ray({1.f / 2048, 0, 0}, {1, 0, 0})});
  const auto k = keys_of("origin", ctx, batch);
  EXPECT_NE(k[1], k[0]);
  EXPECT_EQ(k[2], k[0]);
  EXPECT_NE(k[3], k[0]);  // x keeps 11 bits
}

TEST(Encoders, NonFiniteInputHasDefinedKeys) {
  const EncoderContext ctx{kUnitBox, nullptr};
  Bvh bvh;  // an empty BVH: mlhcc has no cuts and gives 0
  const EncoderContext ctx_bvh{kUnitBox, &bvh};
  const RayBatch batch = make_batch({
      ray({kNaN, kNaN, kNaN}, {1, 0, 0}),
      ray({kInf, kInf, kInf}, {1, 0, 0}),
      ray({-kInf, -kInf, -kInf}, {1, 0, 0}),
      ray({0.5f, 0.5f, 0.5f}, {kNaN, kNaN, kNaN}),
      ray({0.5f, 0.5f, 0.5f}, {kInf, -kInf, kInf}),
      ray({0.5f, 0.5f, 0.5f}, {0, 0, 0}),
      ray({0.5f, 0.5f, 0.5f}, {1, 0, 0}, kNaN),
      ray({0.5f, 0.5f, 0.5f}, {1, 0, 0}, -1.f),
  });
  for (const char* name : {"origin", "reis", "costa", "aila", "twopoint", "mlhcc"}) {
    const auto k = keys_of(std::string(name) + ":bits=64", name == std::string("mlhcc") ? ctx_bvh : ctx, batch);
    EXPECT_EQ(k.size(), batch.size());
    for (size_t i = 0; i < k.size(); ++i) EXPECT_NE(k[i], 0xDEADBEEFull) << name << " ray " << i;
  }
  const auto origin = keys_of("origin:bits=64", ctx, batch);
  EXPECT_EQ(origin[0], 0ull);                   // NaN -> 0
  EXPECT_EQ(origin[1], 0xFFFFFFFFFFFFFFFEull);  // +Inf -> 2^21 - 1
  EXPECT_EQ(origin[2], 0ull);                   // -Inf -> 0
  const auto reis = keys_of("reis:bits=64", ctx, batch);
  EXPECT_EQ(reis[3], 0xE000000000000000ull);  // NaN direction: phi = theta = 0
  const auto tp = keys_of("twopoint:bits=64", ctx, batch);
  // A NaN tmax is no limit; a negative one gives L = 0.
  EXPECT_EQ(tp[6], twopoint_code({0.5f, 0.5f, 0.5f}, {1, 0, 0}, kInf, kUnitBox, 0.25f));
  EXPECT_EQ(tp[7], twopoint_code({0.5f, 0.5f, 0.5f}, {1, 0, 0}, 0.f, kUnitBox, 0.25f));
  EXPECT_NE(tp[6], tp[7]);
  EXPECT_EQ(tp[0], 0ull);
  const auto ml = keys_of("mlhcc:bits=64", ctx_bvh, batch);
  for (uint64_t key : ml) EXPECT_EQ(key, 0ull);
}

TEST(Encoders, RegistryAndParameters) {
  std::vector<std::string> names;
  for (const auto& info : encoder_infos()) names.push_back(info.name);
  // The built-in encoders lead the registry in the comparison's order; a new encoder is appended after them (and
  // needs no change here: docs/extending.md counts the files it touches). Names are unique.
  const std::vector<std::string> builtin{"none", "origin", "reis", "costa", "aila", "twopoint", "mlhcc", "window"};
  ASSERT_GE(names.size(), builtin.size());
  EXPECT_EQ(std::vector<std::string>(names.begin(), names.begin() + static_cast<std::ptrdiff_t>(builtin.size())),
            builtin);
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
  const Bvh bvh = tiny_bvh();
  const EncoderContext ctx{box_of({-1, 0, -1}, {1, 2, 1}), &bvh};
  EXPECT_EQ(make_encoder(parse_plugin_spec("origin"), ctx)->params(), "bits=32,box=-1/0/-1..1/2/1");
  EXPECT_EQ(make_encoder(parse_plugin_spec("reis:bits=64"), ctx)->key_bits(), 64);
  EXPECT_EQ(make_encoder(parse_plugin_spec("twopoint"), ctx)->params(), "bits=32,L=0.25,box=-1/0/-1..1/2/1");
  const auto mlhcc = make_encoder(parse_plugin_spec("mlhcc"), ctx);
  EXPECT_EQ(mlhcc->params(), "bits=32,lambda=0.125,L=0.25,points=both,ranks=compressed,box=-1/0/-1..1/2/1");
  EXPECT_EQ(mlhcc->details(), "levels=1 bits=2 nodes=4");
  EXPECT_EQ(mlhcc->name(), "mlhcc");
  const auto none = make_encoder(parse_plugin_spec("none"), ctx);
  EXPECT_EQ(none->key_bits(), 0);
  EXPECT_EQ(none->params(), "");
  EXPECT_THROW(make_encoder(parse_plugin_spec("morton"), ctx), Error);
  EXPECT_THROW(make_encoder(parse_plugin_spec("origin:bits=16"), ctx), Error);
  EXPECT_THROW(make_encoder(parse_plugin_spec("origin:lambda=0.5"), ctx), Error);
  EXPECT_THROW(make_encoder(parse_plugin_spec("none:bits=32"), ctx), Error);
  EXPECT_THROW(make_encoder(parse_plugin_spec("mlhcc:lambda=1"), ctx), Error);
  EXPECT_THROW(make_encoder(parse_plugin_spec("twopoint:L=-1"), ctx), Error);
  try {
    make_encoder(parse_plugin_spec("reis:bitz=64"), ctx);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("encoder 'reis'"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("bits"), std::string::npos);
  }
  EXPECT_EQ(parse_permute_mode("indirect"), PermuteMode::Indirect);
  EXPECT_THROW(parse_permute_mode("copy"), Error);
}

// The typed record the GPU keys are built from holds the values each encoder read (defaults included).
TEST(Encoders, RecipeHoldsTheTypedParameters) {
  const Bvh bvh = tiny_bvh();
  const EncoderContext ctx{box_of({-1, 0, -1}, {1, 2, 1}), &bvh};
  const KeyRecipe m =
      make_encoder(parse_plugin_spec("mlhcc:bits=64,lambda=0.3,L=0.5,points=origin,ranks=global"), ctx)->recipe();
  EXPECT_EQ(m.kind, KeyKind::Mlhcc);
  EXPECT_EQ(m.bits, 64);
  EXPECT_FLOAT_EQ(m.lambda, 0.3f);
  EXPECT_FLOAT_EQ(m.length_factor, 0.5f);
  EXPECT_FALSE(m.with_end);
  EXPECT_TRUE(m.global_ranks);
  EXPECT_EQ(m.box.hi.y, 2.f);
  const KeyRecipe d = make_encoder(parse_plugin_spec("mlhcc"), ctx)->recipe();
  EXPECT_FLOAT_EQ(d.lambda, 0.125f);
  EXPECT_FLOAT_EQ(d.length_factor, 0.25f);
  EXPECT_TRUE(d.with_end);
  EXPECT_FALSE(d.global_ranks);
  EXPECT_FLOAT_EQ(make_encoder(parse_plugin_spec("twopoint:L=2"), ctx)->recipe().length_factor, 2.f);
  // Every registered encoder's recipe names its own kind (or none), and every kind of encoders/key_code.h's list
  // is made by the encoder of its name: the list and the registry cannot drift apart.
  std::set<std::string> with_kind;
  for (const auto& info : encoder_infos()) {
    const auto encoder = make_encoder(parse_plugin_spec(info.name), ctx);
    const KeyRecipe recipe = encoder->recipe();
    if (recipe.kind == KeyKind::None) continue;  // e.g. window: keys of its own, no device version
    EXPECT_EQ(recipe.bits, encoder->key_bits()) << info.name;
    EXPECT_EQ(key_kind_name(recipe.kind), info.name);
    with_kind.insert(info.name);
  }
  EXPECT_EQ(make_encoder(parse_plugin_spec("none"), ctx)->recipe().kind, KeyKind::None);
  EXPECT_STREQ(key_kind_name(KeyKind::None), "none");
  for (KeyKind kind : kKeyKinds) EXPECT_EQ(with_kind.count(key_kind_name(kind)), 1u) << key_kind_name(kind);
  EXPECT_EQ(with_kind.size(), std::size(kKeyKinds));
  EXPECT_EQ(key_kind_names(), "origin, reis, costa, aila, twopoint, mlhcc");
}

}  // namespace
}  // namespace raycoh
