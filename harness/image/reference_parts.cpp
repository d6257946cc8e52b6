// `raycoh reference`: renders (or finds in the cache) the NoOpt reference that `quality` and `converge` would use
// with the same options, or, with `--shard I/N --out PART`, only shard I's whole frame blocks into a part file
// (a stopped shard run again keeps the blocks it finished in PART.partial);
// `raycoh reference-combine PART...` adds the parts into the cache entry, the same bits as one process's
// (shading/reference.h: frame blocks and part files).
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "core/durable_file.h"
#include "core/error.h"
#include "harness/common/command.h"
#include "harness/common/progress.h"
#include "harness/image/render_cli.h"
#include "harness/image/render_common.h"
#include "harness/image/render_device.h"
#include "records/shard.h"
#include "shading/reference.h"

namespace raycoh {

namespace {

namespace fs = std::filesystem;

struct ReferenceOptions {
  RenderCommon common;
  std::string scene = "cornell";
  int frames = 512;       // --frames: as --ref-frames of quality and converge
  std::string cache_dir;  // --cache
  Shard shard;            // --shard I/N: only this shard, into --out
  std::string out;        // --out: the part file (of --shard, or alone of every block)
};

int run_reference(const ReferenceOptions& o) {
  check_common(o.common, false);
  check_frames("--frames", o.frames);
  check_scene_spec("--scene", o.scene);
  if (!o.shard.whole() && o.out.empty())
    throw Error(
        "--shard I/N needs --out PART: a shard renders one part file (join them with raycoh reference-combine); "
        "--out alone writes every block as one part, and without either the whole reference goes to the cache");
  if (o.out.empty()) {
    auto ls = load(o.scene, o.common.tracer);
    const ReferenceImage ref = obtain_reference(*ls, o.scene, o.common, o.frames, o.cache_dir, "");
    std::printf("reference %s (%s)\n", ref.path.c_str(), ref.kind.c_str());
    return 0;
  }
  ReferenceRequest req = reference_request(o.scene, o.common, o.frames, o.cache_dir);
  reference_shard_frames(o.frames, req.frame_block, o.shard.index, o.shard.count);  // refuses misaligned shards
  check_output_file("--out", o.out);
  if (reference_part_done(o.out, req, o.shard.index, o.shard.count) && !o.common.force) {
    std::printf("reference part %s: already rendered (--force renders it again)\n", o.out.c_str());
    return 0;
  }
  if (fs::exists(o.out) && !o.common.force)
    throw Error(
        fmt::format("--out {} already exists and is not this shard's part; pass --force to replace it, or "
                    "choose another --out",
                    o.out));
  const OutputLock lock(o.out, "--out " + o.out);
  auto ls = load(o.scene, o.common.tracer);
  const auto time = std::make_shared<DeviceTime>();
  if (o.common.device != "cpu") render_reference_on_device(req, *ls, time);
  Progress bar;
  const std::string label = fmt::format("{} reference {}", ls->scene.name, o.shard.text());
  req.progress = [&](int done, int total) { bar.update(0, 1, done - 1, total, label); };
  const double seconds =
      render_reference_part(ls->scene, ls->bvh, req, o.shard.index, o.shard.count, o.out, o.common.force);
  bar.clear();
  const FrameRange range = reference_shard_frames(o.frames, req.frame_block, o.shard.index, o.shard.count);
  std::printf(
      "wrote %s (reference part %s, frames %d..%d, rendered in %.1f s%s; join the parts with raycoh "
      "reference-combine)\n",
      o.out.c_str(), o.shard.text().c_str(), range.first, range.end - 1, seconds, device_time_text(*time).c_str());
  return 0;
}

}  // namespace

BoundCommand bind_reference(CLI::App& parent) {
  struct State {
    ReferenceOptions o;
    RenderText text;
    ProtocolText protocol;
    std::string shard = "0/1";
  };
  auto s = std::make_shared<State>();
  CLI::App* cmd = parent.add_subcommand(
      "reference", "render the NoOpt reference into the cache, or one frame shard of it (--shard I/N --out PART)");
  cmd->add_option("--scene", s->o.scene, "scene")->capture_default_str();
  cmd->add_option("--frames", s->o.frames, "reference frames (as --ref-frames of quality and converge)")
      ->capture_default_str();
  cmd->add_option("--cache", s->o.cache_dir, "reference cache folder (default $RAYCOH_CACHE, else results/cache)");
  cmd->add_option("--shard", s->shard,
                  fmt::format("I/N: render only shard I (0-based) of N, whole blocks of {} frames, into --out",
                              kReferenceFrameBlock))
      ->capture_default_str();
  cmd->add_option("--out", s->o.out, "the part file of --shard (alone: every block as one part)");
  bind_render_common(cmd, s->o.common, s->text);
  bind_protocol(cmd, s->protocol, false);
  return {cmd, [s, cmd](const Provenance&) {
            resolve_render_common(s->o.common, s->text);
            resolve_protocol(cmd, s->protocol, s->o.common, nullptr, nullptr, &s->o.frames, "--frames");
            s->o.shard = parse_shard("--shard", s->shard);
            return run_reference(s->o);
          }};
}

BoundCommand bind_reference_combine(CLI::App& parent) {
  struct State {
    std::vector<std::string> parts;
    std::string cache_dir;
  };
  auto s = std::make_shared<State>();
  CLI::App* cmd = parent.add_subcommand(
      "reference-combine", "add the part files of `reference --shard` into the reference cache entry, exactly");
  cmd->add_option("parts", s->parts, "part files, every shard once (any order)")->required();
  cmd->add_option("--cache", s->cache_dir, "reference cache folder (default $RAYCOH_CACHE, else results/cache)");
  return {cmd, [s](const Provenance&) {
            const Reference ref = combine_reference_parts(s->parts, s->cache_dir);
            if (ref.render_hosts.empty())
              std::printf("combined %zu part(s) -> %s (parts written before format 2 record no render time)\n",
                          s->parts.size(), ref.path.c_str());
            else
              std::printf("combined %zu part(s) -> %s (rendered in %.1f s in all, on %s)\n", s->parts.size(),
                          ref.path.c_str(), ref.render_s, join(ref.render_hosts, ", ").c_str());
            if (!ref.first_half.empty())
              std::printf("first-half reference (for the noise estimate) -> %s\n",
                          half_reference_path(ref.path).c_str());
            if (ref.non_finite > 0)
              std::printf("warning: %llu NaN/Inf frame samples were left out (counted, not added)\n",
                          static_cast<unsigned long long>(ref.non_finite));
            return 0;
          }};
}

}  // namespace raycoh
