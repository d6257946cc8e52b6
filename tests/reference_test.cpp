// The reference cache (shading/reference.h): reused only when every key field matches, invalidated by an edited
// sidecar, an image that is not the one recorded, or a changed scene file.
#include "shading/reference.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "tests/shading_test_util.h"
#include "tests/test_util.h"

namespace raycoh {
namespace {

namespace fs = std::filesystem;

using test::small;

TEST(ReferenceCache, ReusedOnlyWhenEveryKeyFieldMatches) {
  const Scene s = load_scene("cornell");
  const Bvh bvh = build_bvh(s);
  const fs::path dir = test::temp_dir("refcache");
  ReferenceRequest req;
  req.scene_spec = "cornell";
  req.settings = small(24, 16, 5);
  req.frames = 3;
  req.cache_dir = dir.string();
  req.revision = "test-r1";

  const Reference first = get_reference(s, bvh, req);
  EXPECT_FALSE(first.from_cache);
  EXPECT_TRUE(fs::exists(first.path));
  const Reference again = get_reference(s, bvh, req);
  EXPECT_TRUE(again.from_cache);
  EXPECT_EQ(again.path, first.path);
  EXPECT_EQ(std::memcmp(again.image.rgb.data(), first.image.rgb.data(), first.image.rgb.size() * sizeof(float)), 0);

  auto changed = [&](auto&& edit) {
    ReferenceRequest r = req;
    edit(r);
    return get_reference(s, bvh, r);
  };
  EXPECT_FALSE(changed([](ReferenceRequest& r) { r.frames = 4; }).from_cache);
  EXPECT_FALSE(changed([](ReferenceRequest& r) { r.settings.width = 25; }).from_cache);
  EXPECT_FALSE(changed([](ReferenceRequest& r) { r.settings.height = 17; }).from_cache);
  EXPECT_FALSE(changed([](ReferenceRequest& r) { r.settings.seed = 6; }).from_cache);
  EXPECT_FALSE(changed([](ReferenceRequest& r) { r.settings.max_depth = 2; }).from_cache);
  EXPECT_FALSE(changed([](ReferenceRequest& r) { r.revision = "test-r2"; }).from_cache);
  EXPECT_FALSE(changed([](ReferenceRequest& r) { r.tracer = {"embree", ""}; }).from_cache);
  EXPECT_TRUE(get_reference(s, bvh, req).from_cache);  // the original entry is still there

  // A sidecar that does not describe the request (edited, corrupt or missing) means: render again.
  fs::path sidecar = first.path;
  sidecar.replace_extension(".json");
  ASSERT_TRUE(fs::exists(sidecar));
  std::ifstream in(sidecar);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("\"renderer_revision\": \"test-r1\""), std::string::npos) << text;
  test::write_file(sidecar, "{ not json");
  EXPECT_FALSE(get_reference(s, bvh, req).from_cache);
  EXPECT_TRUE(get_reference(s, bvh, req).from_cache);
  fs::remove(first.path);
  EXPECT_FALSE(get_reference(s, bvh, req).from_cache);

  // Another image of the same size in the entry's place, or an edited sidecar field: the checksums catch both.
  const Reference other = changed([](ReferenceRequest& r) { r.settings.seed = 9; });
  fs::copy_file(other.path, first.path, fs::copy_options::overwrite_existing);
  EXPECT_FALSE(get_reference(s, bvh, req).from_cache);
  EXPECT_TRUE(get_reference(s, bvh, req).from_cache);
  std::ifstream side_in(sidecar);
  std::string side((std::istreambuf_iterator<char>(side_in)), std::istreambuf_iterator<char>());
  const size_t at = side.find("\"non_finite_samples\": 0");
  ASSERT_NE(at, std::string::npos) << side;
  side.replace(at, std::strlen("\"non_finite_samples\": 0"), "\"non_finite_samples\": 5");
  test::write_file(sidecar, side);
  const Reference edited = get_reference(s, bvh, req);
  EXPECT_FALSE(edited.from_cache);
  EXPECT_EQ(edited.non_finite, 0u);
  EXPECT_FALSE(fs::exists(fs::path(first.path).replace_extension("").string() + ".lock"));

  EXPECT_NE(renderer_revision().find("r" + std::to_string(kRendererVersion) + "/"), std::string::npos);
  EXPECT_EQ(scene_fingerprint("cornell"), "builtin:cornell");
  EXPECT_THROW(scene_fingerprint("/no/such/scene.glb"), Error);
}

TEST(ReferenceCache, SceneFileFingerprintFollowsItsContent) {
  const fs::path dir = test::temp_dir("fingerprint");
  test::write_file(dir / "a.obj", "v 0 0 0\n");
  const std::string f1 = scene_fingerprint((dir / "a.obj").string());
  EXPECT_EQ(scene_fingerprint((dir / "a.obj").string()), f1);
  test::write_file(dir / "a.obj", "v 0 0 1\n");
  EXPECT_NE(scene_fingerprint((dir / "a.obj").string()), f1);
}

// Eight frame shards of whole blocks, combined, are the single process's reference bit for bit, and the same
// cache entry (get_reference then reads it from the cache).
TEST(ReferenceShards, EightFrameShardsAddUpToTheSingleProcessBitForBit) {
  const Scene s = load_scene("cornell");
  const Bvh bvh = build_bvh(s);
  const fs::path dir = test::temp_dir("refshards");
  ReferenceRequest req;
  req.scene_spec = "cornell";
  req.settings = small(12, 8, 7);
  req.frames = 64;
  req.frame_block = 4;
  req.revision = "test-shards";
  req.cache_dir = (dir / "single").string();
  const Reference single = get_reference(s, bvh, req);
  ASSERT_FALSE(single.from_cache);

  ReferenceRequest sharded = req;
  sharded.cache_dir = (dir / "combined").string();
  std::vector<std::string> parts;
  for (int i = 7; i >= 0; --i) {  // any order
    parts.push_back((dir / ("part" + std::to_string(i))).string());
    render_reference_part(s, bvh, sharded, i, 8, parts.back());
    EXPECT_TRUE(reference_part_done(parts.back(), sharded, i, 8));
    EXPECT_FALSE(reference_part_done(parts.back(), sharded, (i + 1) % 8, 8));
  }
  const Reference combined = combine_reference_parts(parts, sharded.cache_dir);
  EXPECT_EQ(fs::path(combined.path).filename(), fs::path(single.path).filename());
  ASSERT_EQ(combined.image.rgb.size(), single.image.rgb.size());
  EXPECT_EQ(std::memcmp(combined.image.rgb.data(), single.image.rgb.data(), single.image.rgb.size() * sizeof(float)),
            0);
  // The files hold the same pixels (an EXR header also holds its write time, so not the same bytes).
  const Image file_a = read_image(single.path), file_b = read_image(combined.path);
  ASSERT_EQ(file_a.rgb.size(), file_b.rgb.size());
  EXPECT_EQ(std::memcmp(file_a.rgb.data(), file_b.rgb.data(), file_a.rgb.size() * sizeof(float)), 0);
  const Reference reread = get_reference(s, bvh, sharded);
  EXPECT_TRUE(reread.from_cache);
  // The first-half reference (frames 0..31) is kept beside the entry, the same bits both ways, and read back.
  ASSERT_FALSE(single.first_half.empty());
  ASSERT_EQ(combined.first_half.rgb.size(), single.first_half.rgb.size());
  EXPECT_EQ(std::memcmp(combined.first_half.rgb.data(), single.first_half.rgb.data(),
                        single.first_half.rgb.size() * sizeof(float)),
            0);
  EXPECT_TRUE(fs::is_regular_file(half_reference_path(combined.path)));
  ASSERT_EQ(reread.first_half.rgb.size(), single.first_half.rgb.size());
  EXPECT_EQ(std::memcmp(reread.first_half.rgb.data(), single.first_half.rgb.data(),
                        single.first_half.rgb.size() * sizeof(float)),
            0);
  EXPECT_NE(std::memcmp(single.first_half.rgb.data(), single.image.rgb.data(), single.image.rgb.size() * sizeof(float)),
            0);
  EXPECT_EQ(half_reference_path("/a/b/cornell-0123.exr"), "/a/b/cornell-0123-half1.exr");

  // Two shards of the same blocks give the same bits too.
  ReferenceRequest two = req;
  two.cache_dir = (dir / "two").string();
  render_reference_part(s, bvh, two, 0, 2, (dir / "two0").string());
  render_reference_part(s, bvh, two, 1, 2, (dir / "two1").string());
  const Reference pair = combine_reference_parts({(dir / "two1").string(), (dir / "two0").string()}, two.cache_dir);
  EXPECT_EQ(std::memcmp(pair.image.rgb.data(), single.image.rgb.data(), single.image.rgb.size() * sizeof(float)), 0);

  // What does not add up is refused, naming the file.
  std::vector<std::string> seven(parts.begin(), parts.end() - 1);
  EXPECT_NE(test::error_of([&] {
              combine_reference_parts(seven, sharded.cache_dir);
            }).find("1 of 8 reference shard(s) missing: 0/8"),
            std::string::npos);
  std::vector<std::string> twice = parts;
  twice.push_back(parts[0]);
  EXPECT_NE(test::error_of([&] { combine_reference_parts(twice, sharded.cache_dir); }).find("are both shard 7/8"),
            std::string::npos);
  EXPECT_NE(test::error_of([&] {
              combine_reference_parts({parts[0], (dir / "two0").string()}, two.cache_dir);
            }).find("disagree on the shard count"),
            std::string::npos);
  ReferenceRequest other = req;
  other.settings.seed = 8;
  render_reference_part(s, bvh, other, 0, 8, (dir / "other").string());
  std::vector<std::string> mixed(parts.begin(), parts.end() - 1);
  mixed.push_back((dir / "other").string());
  EXPECT_NE(test::error_of([&] { combine_reference_parts(mixed, sharded.cache_dir); }).find("key field seed (7 vs 8)"),
            std::string::npos);
  // A part cut short.
  const std::string cut = (dir / "cut").string();
  fs::copy_file(parts[0], cut);
  fs::resize_file(cut, fs::file_size(cut) - 100);
  std::vector<std::string> with_cut(parts.begin() + 1, parts.end());
  with_cut.push_back(cut);
  EXPECT_NE(test::error_of([&] { combine_reference_parts(with_cut, sharded.cache_dir); }).find(cut), std::string::npos);
}

TEST(ReferenceShards, MisalignedShardsAreRefusedNamingTheValidCounts) {
  EXPECT_EQ(reference_shard_frames(4096, 64, 3, 8).first, 1536);
  EXPECT_EQ(reference_shard_frames(4096, 64, 3, 8).end, 2048);
  EXPECT_EQ(reference_shard_frames(100, 64, 0, 1).end, 100);
  const std::string e = test::error_of([] { reference_shard_frames(512, 64, 0, 3); });
  EXPECT_NE(e.find("--shard 0/3"), std::string::npos) << e;
  EXPECT_NE(e.find("whole blocks of 64 frames"), std::string::npos) << e;
  EXPECT_NE(e.find("valid shard counts: 1, 2, 4, 8"), std::string::npos) << e;
  EXPECT_NE(test::error_of([] { reference_shard_frames(100, 64, 1, 2); }).find("valid shard counts: 1"),
            std::string::npos);
  EXPECT_NE(test::error_of([] { reference_shard_frames(128, 64, 0, 4); }).find("valid shard counts: 1, 2"),
            std::string::npos);
}

}  // namespace
}  // namespace raycoh
