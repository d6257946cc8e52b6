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
}  // namespace
}  // namespace raycoh
