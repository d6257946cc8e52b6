// `raycoh scenes info SCENE`: a scene's features, the stages it skips, what the loader did (extensions, dropped
// primitives, instancing, warnings), its camera and BVH statistics.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "bvh/bvh_build.h"
#include "harness/common/command.h"
#include "scenes/scene.h"

namespace raycoh {

namespace {

void print_scene_info(const std::string& spec) {
  const Scene scene = load_scene(spec);
  const SceneFeatures f = analyse(scene);
  std::printf("scene        %s (%s)\n", scene.name.c_str(), scene.source.c_str());
  std::printf("triangles    %zu (%u zero-area)\n", f.triangles, scene.degenerate_tris);
  std::printf("vertices     %zu%s\n", scene.positions.size(), scene.generated_normals ? " (normals generated)" : "");
  std::printf("bounds       [%g %g %g] .. [%g %g %g]\n", scene.bounds.lo.x, scene.bounds.lo.y, scene.bounds.lo.z,
              scene.bounds.hi.x, scene.bounds.hi.y, scene.bounds.hi.z);
  if (scene.rebase_scale != 1.f || scene.rebase_offset.x != 0.f || scene.rebase_offset.y != 0.f ||
      scene.rebase_offset.z != 0.f)
    std::printf("rebased      (source - [%.9g %.9g %.9g]) x %g, exactly (docs/stability.md)\n", scene.rebase_offset.x,
                scene.rebase_offset.y, scene.rebase_offset.z, scene.rebase_scale);
  std::printf("materials    %zu:", scene.materials.size());
  for (int c = 0; c < kMaterialClassCount; ++c)
    std::printf(" %s %zu", to_string(static_cast<MaterialClass>(c)), f.materials_per_class[c]);
  std::printf("\nfeatures     glossy %s, transmissive %s, emissive %s (%zu emitting triangles), textures %s\n",
              f.has_glossy ? "yes" : "no", f.has_transmissive ? "yes" : "no", f.has_emissive ? "yes" : "no",
              scene.emissive_tris.size(), f.has_textures ? "yes" : "no");
  std::printf("lighting     %s\n", scene.env.enabled       ? "sky + sun (environment)"
                                   : !scene.lights.empty() ? "punctual lights and scene emitters"
                                                           : "scene emitters");
  for (const PunctualLight& l : scene.lights) {
    std::printf("light        %s '%s': intensity [%g %g %g]", to_string(l.type), l.name.c_str(), l.intensity.x,
                l.intensity.y, l.intensity.z);
    if (l.type != LightType::Directional)
      std::printf(" at [%g %g %g], range %s", l.position.x, l.position.y, l.position.z,
                  l.range > 0.f ? fmt::format("{:g}", l.range).c_str() : "infinite");
    if (l.type != LightType::Point) std::printf(", direction [%g %g %g]", l.direction.x, l.direction.y, l.direction.z);
    if (l.type == LightType::Spot)
      std::printf(", cone %g..%g deg", std::acos(std::min(1.f, l.cos_inner)) * 57.29578f,
                  std::acos(std::min(1.f, l.cos_outer)) * 57.29578f);
    std::printf("\n");
  }
  const std::string view = scene.camera.ortho_half_height > 0.f
                               ? fmt::format("orthographic, half-height {:g}", scene.camera.ortho_half_height)
                               : fmt::format("vfov {:g}", scene.camera.vfov_deg);
  std::printf("camera       %s: eye [%g %g %g] target [%g %g %g] %s\n",
              scene.camera.from_file ? "from the scene" : "default framing of the bounds", scene.camera.eye.x,
              scene.camera.eye.y, scene.camera.eye.z, scene.camera.target.x, scene.camera.target.y,
              scene.camera.target.z, view.c_str());
  for (const std::string& s : f.skipped_stages) std::printf("skipped      %s\n", s.c_str());
  for (const std::string& s : scene.load_notes) std::printf("loader       %s\n", s.c_str());
  const Bvh bvh = build_bvh(scene);
  std::printf("bvh          %zu inner nodes, %zu leaves, depth %zu, SAH cost %.2f, %.2f MiB, built in %.3f s\n",
              bvh.stats.inner_nodes, bvh.stats.leaves, bvh.stats.max_depth, bvh.stats.sah_cost,
              bvh.stats.bytes / 1048576.0, bvh.stats.build_seconds);
}

}  // namespace

BoundCommand bind_scenes_info(CLI::App& parent) {
  CLI::App* scenes = parent.add_subcommand("scenes", "scene utilities");
  scenes->require_subcommand(1);
  auto spec = std::make_shared<std::string>();
  CLI::App* cmd = scenes->add_subcommand("info", "print a scene's features, the stages it skips, its BVH");
  cmd->add_option("scene", *spec, "built-in name or .gltf/.glb/.obj path")->required();
  return {cmd, [spec](const Provenance&) {
            print_scene_info(*spec);
            return 0;
          }};
}

}  // namespace raycoh
