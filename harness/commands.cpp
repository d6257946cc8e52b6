#include "harness/commands.h"

#include <algorithm>
#include <cstdio>
#include <fmt/format.h>

#include "core/error.h"
#include "bvh/bvh_build.h"
#include "tracers/tracer.h"
#include "encoders/encoder.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "generators/primary.h"
#include "harness/csv.h"

namespace raycoh {

void run_list() {
  std::printf("Generators (--generators name[:key=value,...]):\n");
  for (const auto& g : generator_infos()) std::printf("  %-10s %s\n  %-10s   params: %s\n", g.name.c_str(), g.summary.c_str(), "", g.params.c_str());
  std::printf("\nEncoders:\n");
  for (const auto& e : encoder_infos()) std::printf("  %-10s %s\n  %-10s   params: %s\n", e.name.c_str(), e.summary.c_str(), "", e.params.c_str());
  std::printf("\nTracers (--tracers name[:key=value,...]):\n");
  for (const auto& t : tracer_infos()) std::printf("  %-10s %s\n  %-10s   params: %s\n", t.name.c_str(), t.summary.c_str(), "", t.params.c_str());
  std::printf("\nBuilt-in scenes (--scenes name[:key=value,...], or any .gltf/.glb/.obj path or folder):\n");
  for (const auto& s : builtin_scene_names()) std::printf("  %-10s %s\n", s.c_str(), builtin_scene_summary(s).c_str());
}

void run_scene_info(const std::string& spec) {
  const Scene scene = load_scene(spec);
  const SceneFeatures f = analyse(scene);
  std::printf("scene        %s (%s)\n", scene.name.c_str(), scene.source.c_str());
  std::printf("triangles    %zu (%u zero-area)\n", f.triangles, scene.degenerate_tris);
  std::printf("vertices     %zu%s\n", scene.positions.size(), scene.generated_normals ? " (normals generated)" : "");
  std::printf("bounds       [%g %g %g] .. [%g %g %g]\n", scene.bounds.lo.x, scene.bounds.lo.y, scene.bounds.lo.z,
              scene.bounds.hi.x, scene.bounds.hi.y, scene.bounds.hi.z);
  std::printf("materials    %zu:", scene.materials.size());
  for (int c = 0; c < kMaterialClassCount; ++c)
    std::printf(" %s %zu", to_string(static_cast<MaterialClass>(c)), f.materials_per_class[c]);
  std::printf("\nfeatures     glossy %s, transmissive %s, emissive %s (%zu emitting triangles), textures %s\n",
              f.has_glossy ? "yes" : "no", f.has_transmissive ? "yes" : "no", f.has_emissive ? "yes" : "no",
              scene.emissive_tris.size(), f.has_textures ? "yes" : "no");
  std::printf("lighting     %s\n", scene.env.enabled ? "sky + sun (environment)" : "scene emitters");
  std::printf("camera       %s: eye [%g %g %g] target [%g %g %g] vfov %g\n",
              scene.camera.from_file ? "from the scene" : "default framing of the bounds", scene.camera.eye.x, scene.camera.eye.y,
              scene.camera.eye.z, scene.camera.target.x, scene.camera.target.y, scene.camera.target.z,
              scene.camera.vfov_deg);
  for (const std::string& s : f.skipped_stages) std::printf("skipped      %s\n", s.c_str());
  const Bvh bvh = build_bvh(scene);
  std::printf("bvh          %zu inner nodes, %zu leaves, depth %zu, SAH cost %.2f, %.2f MiB, built in %.3f s\n",
              bvh.stats.inner_nodes, bvh.stats.leaves, bvh.stats.max_depth, bvh.stats.sah_cost,
              bvh.stats.bytes / 1048576.0, bvh.stats.build_seconds);
}

void run_rays(const RaysOptions& o, const Provenance& provenance) {
  auto generator = make_generator(o.generator);
  // Checked up front (no scene needed) so a bad name fails before any work; made for the scene below.
  if (std::none_of(encoder_infos().begin(), encoder_infos().end(),
                   [&](const EncoderInfo& e) { return e.name == o.encoder.name; }))
    make_encoder(o.encoder, EncoderContext{});
  if (o.out.empty()) throw Error("--out is required: the CSV file to write the rays to");
  const Scene scene = load_scene(o.scene);
  const Bvh bvh = build_bvh(scene);
  auto tracer = make_tracer({"cpu", ""}, scene, bvh);
  const auto order = make_pixel_order(o.width, o.height, RayOrder::Tile, 8, 8);
  const PrimaryBatch primary =
      make_primary_rays(scene.camera, o.width, o.height, order, o.seed, static_cast<uint32_t>(o.frame), true);
  std::vector<Hit> hits(primary.rays.size());
  tracer->trace(primary.rays.data(), primary.rays.size(), hits.data());
  const GBuffer gbuffer = make_gbuffer(scene, primary, hits);
  RayBatch batch;
  GenerationStats stats;
  generator->generate(scene, gbuffer, o.seed, batch, stats);

  std::vector<std::string> columns = {"index",  "pixel_x",  "pixel_y",  "frame",    "org_x",          "org_y",
                                      "org_z",  "dir_x",    "dir_y",    "dir_z",    "tmin",           "tmax",
                                      "normal_x", "normal_y", "normal_z", "material_class", "pdf", "weight_r",
                                      "weight_g", "weight_b"};
  if (batch.has_groups()) columns.insert(columns.end(), {"tile", "group", "group_type"});
  // Keys in the batch's own order (not sorted), with the quantisation box in a comment line above the header.
  const auto encoder = make_encoder(o.encoder, EncoderContext{scene.bounds, &bvh});
  std::vector<uint64_t> keys;
  std::string comment;
  if (encoder->key_bits() > 0) {
    keys.resize(batch.size());
    encoder->encode(batch, keys.data());
    columns.push_back("key");
    comment = fmt::format("encoder={} {}", encoder->name(), encoder->params());  // params end with box=lo..hi
  }
  // A ray dump is one frame: never appended to.
  CsvWriter csv(o.out, columns, CsvWriter::Resume::No, comment);
  for (size_t i = 0; i < batch.size(); ++i) {
    const Ray& r = batch.rays[i];
    const Vec3 n = batch.normal[i], w = batch.weight[i];
    std::vector<std::string> row = {std::to_string(i), std::to_string(batch.pixel[i] % o.width), std::to_string(batch.pixel[i] / o.width),
                   std::to_string(o.frame), fmt::format("{:.9g}", r.org.x), fmt::format("{:.9g}", r.org.y),
                   fmt::format("{:.9g}", r.org.z), fmt::format("{:.9g}", r.dir.x), fmt::format("{:.9g}", r.dir.y),
                   fmt::format("{:.9g}", r.dir.z), fmt::format("{:.9g}", r.tmin), fmt::format("{:.9g}", r.tmax),
                   fmt::format("{:.9g}", n.x), fmt::format("{:.9g}", n.y), fmt::format("{:.9g}", n.z),
                   to_string(batch.material[i]), fmt::format("{:.9g}", batch.pdf[i]), fmt::format("{:.9g}", w.x),
                   fmt::format("{:.9g}", w.y), fmt::format("{:.9g}", w.z)};
    if (batch.has_groups())
      row.insert(row.end(), {std::to_string(batch.tile[i]), std::to_string(batch.group[i]),
                             to_string(batch.group_type[i])});
    if (!keys.empty()) row.push_back(fmt::format("{:0{}x}", keys[i], encoder->key_bits() / 4));
    csv.write_row(row);
  }
  csv.finish();
  std::printf("wrote %zu rays of %s / %s [%s], frame %d, %dx%d, seed %u to %s (%zu below the geometric surface, "
              "%zu below the shading hemisphere, %zu non-finite; %s)\n",
              batch.size(), scene.name.c_str(), o.generator.name.c_str(), generator->params().c_str(), o.frame,
              o.width, o.height, o.seed, o.out.c_str(), stats.below_geometric, stats.below_shading, stats.non_finite,
              provenance.git_revision.c_str());
}

}  // namespace raycoh
