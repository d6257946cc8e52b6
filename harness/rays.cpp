#include "harness/rays.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <tuple>

#include "bvh/bvh_build.h"
#include "core/durable_file.h"
#include "core/error.h"
#include "encoders/encoder.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "harness/common/cli.h"
#include "harness/common/command.h"
#include "harness/common/memory_check.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "records/ray_row.h"
#include "records/record_csv.h"
#include "tracers/tracer.h"

namespace raycoh {

namespace {

void check_rays(const RaysOptions& o) {
  if (o.width < 1 || o.width > 16384 || o.height < 1 || o.height > 16384)
    throw Error(fmt::format("--res {}x{}: width and height must be in [1, 16384]", o.width, o.height));
  if (o.frame < 0 || o.frame > (1 << 30)) throw Error(fmt::format("--frame {}: must be in [0, 2^30]", o.frame));
  if (o.out.empty()) throw Error("--out is required: the CSV file to write the rays to");
  check_output_file("--out", o.out);
  check_memory(fmt::format("--res {}x{}", o.width, o.height), experiment_bytes(o.width, o.height));
  if (!o.force && std::filesystem::exists(o.out))
    throw Error(fmt::format("--out {} already exists; pass --force to replace it, or choose another --out", o.out));
}

}  // namespace

int run_rays(const RaysOptions& o, const Provenance& provenance) {
  check_rays(o);
  auto generator = make_generator(o.generator);
  // Checked up front (no scene needed) so a bad name fails before any work; made for the scene below.
  if (std::none_of(encoder_infos().begin(), encoder_infos().end(),
                   [&](const EncoderInfo& e) { return e.name == o.encoder.name; }))
    make_encoder(o.encoder, EncoderContext{});
  const Scene scene = load_scene(o.scene);
  const Bvh bvh = build_bvh(scene);
  auto tracer = make_tracer({"cpu", ""}, scene, bvh);
  const auto order = make_pixel_order(o.width, o.height, RayOrder::Tile, 8, 8);
  const GBuffer gbuffer =
      first_hits(scene, *tracer, o.width, o.height, order, o.seed, static_cast<uint32_t>(o.frame), true).gbuffer;
  RayBatch batch;
  GenerationStats stats;
  generator->generate(scene, gbuffer, o.seed, batch, stats);

  // Keys in the batch's own order (not sorted), with the quantisation box in a comment line above the header.
  const auto encoder = make_encoder(o.encoder, EncoderContext{scene.bounds, &bvh});
  std::vector<uint64_t> keys;
  std::string comment;
  if (encoder->key_bits() > 0) {
    keys.resize(batch.size());
    encoder->encode(batch, keys.data());
    comment = fmt::format("encoder={} {}", encoder->name(), encoder->params());  // params end with box=lo..hi
  }
  const Schema<RayRow> schema = rays_schema(batch.has_groups(), !keys.empty());
  // A ray dump is one frame: never appended. An existing --out was refused above unless --force.
  RecordCsv<RayRow> csv(o.out, schema, CsvWriter::Options::once(true, {}, comment));
  for (size_t i = 0; i < batch.size(); ++i) {
    RayRow row = ray_row(batch, i, o.width, o.frame);
    if (!keys.empty()) row.key = fmt::format("{:0{}x}", keys[i], encoder->key_bits() / 4);
    csv.write(row);
  }
  csv.finish();
  std::printf(
      "wrote %zu rays of %s / %s [%s], frame %d, %dx%d, seed %u to %s (%zu below the geometric surface, "
      "%zu below the shading hemisphere, %zu non-finite; %s)\n",
      batch.size(), scene.name.c_str(), o.generator.name.c_str(), generator->params().c_str(), o.frame, o.width,
      o.height, o.seed, o.out.c_str(), stats.below_geometric, stats.below_shading, stats.non_finite,
      provenance.git_revision.c_str());
  return 0;
}

BoundCommand bind_rays(CLI::App& parent) {
  struct State {
    RaysOptions o;
    std::string generator, encoder, res;
  };
  auto s = std::make_shared<State>();
  s->generator = s->o.generator.text();
  s->encoder = s->o.encoder.text();
  s->res = fmt::format("{}x{}", s->o.width, s->o.height);
  CLI::App* cmd = parent.add_subcommand("rays", "dump one frame's secondary ray batch as CSV, one row per ray");
  cmd->add_option("--scene", s->o.scene, "scene")->required();
  cmd->add_option("--generator", s->generator, "generator")->capture_default_str();
  cmd->add_option("--encoder", s->encoder, "encoder whose key is written per ray (hex)")->capture_default_str();
  cmd->add_option("--frame", s->o.frame, "frame index")->capture_default_str();
  cmd->add_option("--res", s->res, "resolution WxH")->capture_default_str();
  cmd->add_option("--seed", s->o.seed, "random seed")->capture_default_str();
  cmd->add_option("--out", s->o.out, "CSV file to write")->required();
  cmd->add_flag("--force", s->o.force, "replace an existing --out");
  return {cmd, [s](const Provenance& provenance) {
            s->o.generator = parse_plugin_spec(s->generator);
            s->o.encoder = parse_plugin_spec(s->encoder);
            std::tie(s->o.width, s->o.height) = parse_res("--res", s->res);
            return run_rays(s->o, provenance);
          }};
}

}  // namespace raycoh
