// The reference cache (shading/reference.h): reused only when every key field matches, invalidated by an edited
// sidecar, an image that is not the one recorded, or a changed scene file.
#include "shading/reference.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

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

// What does not add up is refused, naming the file: `parts` are the eight shards of `req` combined into
// `cache_dir`, dir/two0 the first of two shards combined into `two_cache_dir`.
void expect_bad_part_sets_refused(const Scene& s, const Bvh& bvh, const ReferenceRequest& req,
                                  const std::vector<std::string>& parts, const fs::path& dir,
                                  const std::string& cache_dir, const std::string& two_cache_dir) {
  std::vector<std::string> seven(parts.begin(), parts.end() - 1);
  EXPECT_NE(
      test::error_of([&] { combine_reference_parts(seven, cache_dir); }).find("1 of 8 reference shard(s) missing: 0/8"),
      std::string::npos);
  std::vector<std::string> twice = parts;
  twice.push_back(parts[0]);
  EXPECT_NE(test::error_of([&] { combine_reference_parts(twice, cache_dir); }).find("are both shard 7/8"),
            std::string::npos);
  EXPECT_NE(test::error_of([&] {
              combine_reference_parts({parts[0], (dir / "two0").string()}, two_cache_dir);
            }).find("disagree on the shard count"),
            std::string::npos);
  ReferenceRequest other = req;
  other.settings.seed = 8;
  render_reference_part(s, bvh, other, 0, 8, (dir / "other").string());
  std::vector<std::string> mixed(parts.begin(), parts.end() - 1);
  mixed.push_back((dir / "other").string());
  EXPECT_NE(test::error_of([&] { combine_reference_parts(mixed, cache_dir); }).find("key field seed (7 vs 8)"),
            std::string::npos);
  // A part cut short.
  const std::string cut = (dir / "cut").string();
  fs::copy_file(parts[0], cut);
  fs::resize_file(cut, fs::file_size(cut) - 100);
  std::vector<std::string> with_cut(parts.begin() + 1, parts.end());
  with_cut.push_back(cut);
  EXPECT_NE(test::error_of([&] { combine_reference_parts(with_cut, cache_dir); }).find(cut), std::string::npos);
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

  expect_bad_part_sets_refused(s, bvh, req, parts, dir, sharded.cache_dir, two.cache_dir);
}

// The combined entry's sidecar (JSON beside the image).
nlohmann::json sidecar_of(const Reference& ref) {
  std::ifstream in(fs::path(ref.path).replace_extension(".json"));
  return nlohmann::json::parse(in);
}

bool same_pixels(const Image& a, const Image& b) {
  return a.rgb.size() == b.rgb.size() && std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

// A shard stopped after k blocks (here by a throw from its progress callback, after the third block was written and
// synced; then a torn fourth block, as a kill leaves it) keeps them: run again, it renders only the other blocks,
// and the combined reference is the single process's bit for bit. The combined sidecar sums the parts' render
// seconds and names their hosts. A .partial of another part is refused unless replaced.
TEST(ReferenceShards, AStoppedPartKeepsItsFinishedBlocks) {
  const Scene s = load_scene("cornell");
  const Bvh bvh = build_bvh(s);
  const fs::path dir = test::temp_dir("refresume");
  ReferenceRequest req;
  req.scene_spec = "cornell";
  req.settings = small(12, 8, 5);
  req.frames = 64;
  req.frame_block = 4;  // 8 blocks per shard of 2
  req.revision = "test-resume";
  req.cache_dir = (dir / "single").string();
  const Reference single = get_reference(s, bvh, req);

  ReferenceRequest sharded = req;
  sharded.cache_dir = (dir / "combined").string();
  const std::string p0 = (dir / "part0").string(), p1 = (dir / "part1").string();
  int frames = 0;
  sharded.progress = [&](int, int) {
    if (++frames == 14) throw Error("stopped");  // in block 4, after blocks 1 .. 3 went to disk
  };
  EXPECT_EQ(test::error_of([&] { render_reference_part(s, bvh, sharded, 0, 2, p0); }), "stopped");
  EXPECT_FALSE(fs::exists(p0));
  ASSERT_TRUE(fs::exists(p0 + ".partial"));
  EXPECT_FALSE(reference_part_done(p0, sharded, 0, 2));
  {
    std::ofstream torn(p0 + ".partial", std::ios::binary | std::ios::app);
    torn << std::string(1000, '\x7f');  // part of block 4's bytes
  }
  frames = 0;
  sharded.progress = [&](int, int) { ++frames; };
  render_reference_part(s, bvh, sharded, 0, 2, p0);
  EXPECT_EQ(frames, 32 - 3 * 4);  // only blocks 4 .. 8
  EXPECT_FALSE(fs::exists(p0 + ".partial"));
  EXPECT_TRUE(reference_part_done(p0, sharded, 0, 2));

  // Shard 1: a .partial whose second block line does not match its bytes keeps only the first block.
  sharded.progress = nullptr;
  render_reference_part(s, bvh, sharded, 1, 2, p1);
  std::ifstream in(p1, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t block_bytes = 12 * 8 * 32;
  const size_t first = bytes.find('\n') + 1 + block_bytes;          // block 0's line
  const size_t second = bytes.find('\n', first) + 1 + block_bytes;  // block 1's line
  ASSERT_EQ(bytes.compare(second, 8, "block 1 "), 0);
  bytes[second + 8] = bytes[second + 8] == '0' ? '1' : '0';  // its checksum
  test::write_file(p1 + ".partial", bytes.substr(0, bytes.find('\n', second) + 1));
  frames = 0;
  sharded.progress = [&](int, int) { ++frames; };
  render_reference_part(s, bvh, sharded, 1, 2, p1);
  EXPECT_EQ(frames, 32 - 4);

  const Reference combined = combine_reference_parts({p1, p0}, sharded.cache_dir);
  EXPECT_EQ(fs::path(combined.path).filename(), fs::path(single.path).filename());
  EXPECT_TRUE(same_pixels(combined.image, single.image));
  EXPECT_TRUE(same_pixels(read_image(combined.path), read_image(single.path)));
  const nlohmann::json side = sidecar_of(combined);
  EXPECT_GT(side.at("render_seconds").get<double>(), 0);
  EXPECT_DOUBLE_EQ(side.at("render_seconds").get<double>(), combined.render_s);
  EXPECT_EQ(side.at("render_hosts").size(), 1u);
  EXPECT_EQ(side.at("parts").get<int>(), 2);
  EXPECT_FALSE(side.contains("parts_without_render_time"));
  EXPECT_TRUE(get_reference(s, bvh, sharded).from_cache);  // the sidecar's new fields keep it valid

  // Another part's .partial is not thrown away unasked.
  fs::copy_file(p0, p1 + ".partial", fs::copy_options::overwrite_existing);
  const std::string e = test::error_of([&] { render_reference_part(s, bvh, sharded, 1, 2, p1); });
  EXPECT_NE(e.find(p1 + ".partial holds another reference part (shard 0/2 vs 1/2)"), std::string::npos) << e;
  render_reference_part(s, bvh, sharded, 1, 2, p1, true);
  EXPECT_TRUE(reference_part_done(p1, sharded, 1, 2));
}

// Part files of revision 4919fdd (format 1, no block lines), made by that revision's `raycoh reference --scene
// cornell --res 4x3 --seed 3 --frames 256 --shard I/2 --out tests/data/ref-part-4919fdd-I-of-2.part`, are still
// read and combined, alone or beside a part of today's format, into the reference this code renders for their key.
TEST(ReferenceShards, PartsOfRevision4919fddAreStillCombined) {
  const fs::path data = fs::path(RAYCOH_SOURCE_DIR) / "tests" / "data";
  const std::string old0 = (data / "ref-part-4919fdd-0-of-2.part").string(),
                    old1 = (data / "ref-part-4919fdd-1-of-2.part").string();
  std::ifstream in(old0, std::ios::binary);
  std::string line;
  std::getline(in, line);
  const nlohmann::json key = nlohmann::json::parse(line).at("key");
  ASSERT_EQ(nlohmann::json::parse(line).at("raycoh_reference_part").get<int>(), 1);
  const Scene s = load_scene("cornell");
  const Bvh bvh = build_bvh(s);
  const fs::path dir = test::temp_dir("refformat1");
  ReferenceRequest req;
  req.scene_spec = "cornell";
  req.settings = small(4, 3, key.at("seed").get<uint32_t>());
  req.frames = 256;
  req.revision = key.at("renderer_revision").get<std::string>();
  req.cache_dir = (dir / "single").string();
  ASSERT_EQ(reference_key(req), key.dump());
  const Reference single = get_reference(s, bvh, req);
  ASSERT_FALSE(single.from_cache);
  EXPECT_TRUE(reference_part_done(old0, req, 0, 2));

  const Reference both_old = combine_reference_parts({old1, old0}, (dir / "old").string());
  EXPECT_EQ(fs::path(both_old.path).filename(), fs::path(single.path).filename());
  EXPECT_TRUE(same_pixels(both_old.image, single.image));
  EXPECT_EQ(sidecar_of(both_old).at("parts_without_render_time").get<int>(), 2);
  EXPECT_EQ(sidecar_of(both_old).at("render_seconds").get<double>(), 0);

  const std::string new1 = (dir / "new1").string();
  render_reference_part(s, bvh, req, 1, 2, new1);
  const Reference mixed = combine_reference_parts({old0, new1}, (dir / "mixed").string());
  EXPECT_TRUE(same_pixels(mixed.image, single.image));
  EXPECT_EQ(sidecar_of(mixed).at("parts_without_render_time").get<int>(), 1);
  EXPECT_GT(sidecar_of(mixed).at("render_seconds").get<double>(), 0);
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
