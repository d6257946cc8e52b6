#include "harness/image/render.h"

// `raycoh render`: one scene, one generator, N frames (frames 0..N-1, seed --seed) through shading/path_tracer.h;
// writes the mean image (.exr float, .png tone-mapped, .pfm) and the --crop regions beside it. --device cuda renders
// the frames on the device path tracer (harness/image/render_device.h) instead.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "core/durable_file.h"
#include "core/error.h"
#include "harness/common/command.h"
#include "harness/common/progress.h"
#include "harness/image/render_cli.h"
#include "harness/image/render_common.h"
#include "harness/image/render_device.h"
#include "records/speed_interval.h"
#include "shading/path_tracer.h"

namespace raycoh {

namespace fs = std::filesystem;

namespace {

// The frames on the CPU path tracer; returns the timing line.
std::string render_cpu(const RenderOptions& o, LoadedScene& ls, Generator& generator, Accumulator& acc) {
  PathTracer pt(ls.scene, *ls.tracer, generator, settings_of(o.common, o.common.seed));
  FrameStats total;
  Progress bar;
  for (int f = 0; f < o.frames; ++f) {
    total.add(pt.render_frame(static_cast<uint32_t>(f), acc));
    bar.update(0, 1, f, o.frames, fmt::format("{} {}", ls.scene.name, o.generator.text()));
  }
  bar.clear();
  return fmt::format("render {:.2f} s (trace {:.2f} s, generation {:.3f} s); {:.3g} rays ({:.2f} MRay/s traced)",
                     total.wall_s, total.trace_s, total.gen_s, static_cast<double>(total.rays()),
                     total.trace_s > 0 ? static_cast<double>(total.rays()) / total.trace_s * 1e-6 : 0.0);
}

// "median M [lo, hi] (L% interval over N frames)" of the frames' figures (NaNs left out), or "n/a".
std::string spread(std::vector<double> v, const char* unit) {
  std::erase_if(v, [](double x) { return std::isnan(x); });
  if (v.empty()) return "n/a";
  const MedianInterval m = median_interval(v);
  if (m.level == 0) return fmt::format("{:.3f} {} (one frame, no interval)", m.median, unit);
  return fmt::format("median {:.3f} {} [{:.3f}, {:.3f}] ({:.0f}% interval over {} frames)", m.median, unit, m.lo, m.hi,
                     100 * m.level, v.size());
}

// The frames on the device path tracer (harness/image/render_device.h); returns the timing lines, labelled with
// their clock: totals over the frames, then each figure's median across frames with its interval.
std::string render_device(const RenderOptions& o, LoadedScene& ls, Generator& generator, Accumulator& acc) {
  Progress bar;
  const auto t0 = std::chrono::steady_clock::now();
  const DeviceRenderTotals t = render_on_device(
      ls, generator, settings_of(o.common, o.common.seed), o.common.device, o.frames, acc,
      [&](int f) { bar.update(0, 1, f, o.frames, fmt::format("{} {} (device)", ls.scene.name, o.generator.text())); });
  bar.clear();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::string stages;
  for_each_stage(t.stages, [&](const char* name, double ms) {
    stages += fmt::format("{}{} {:.3f}", stages.empty() ? "" : ", ", name, ms / o.frames);
  });
  const auto rate = [](double rays, double ms) { return ms > 0 ? rays / ms * 1e-3 : 0.0; };
  const DeviceStageMs& s = t.stages;
  return fmt::format(
      "device path tracer on {}: GPU time {:.3f} ms per frame ({}: CUDA events around each frame); wall {:.2f} s; "
      "{:.3g} rays ({:.2f} MRay/s of {} GPU time)\n  by stage, ms per frame ({}; the rest of the frame in none): {}\n"
      "  trace by bounce ({}): first {:.3f} ms per frame, {:.2f} MRay/s; second {:.3f} ms per frame, {:.2f} MRay/s\n"
      "  across frames ({}): GPU time per frame {}; first bounce's trace {}; second's {}",
      t.device, t.gpu_ms / o.frames, t.clock, wall, static_cast<double>(t.rays), rate(double(t.rays), t.gpu_ms),
      t.clock, t.clock, stages, t.clock, s.first_trace / o.frames, rate(s.first_rays, s.first_trace),
      s.second_trace / o.frames, rate(s.second_rays, s.second_trace), t.clock, spread(t.frame_ms, "ms"),
      spread(t.first_mrays, "MRay/s"), spread(t.second_mrays, "MRay/s"));
}

}  // namespace

int run_render(const RenderOptions& o, const Provenance& provenance) {
  check_common(o.common, false);
  check_frames("--frames", o.frames);
  check_scene_spec("--scene", o.scene);
  check_crops(o.crops, o.common.width, o.common.height);
  check_output_image_path("--out", o.out);
  check_output_file("--out", o.out);
  if (!o.common.force && fs::exists(o.out))
    throw Error(fmt::format("--out {} already exists; pass --force to replace it, or choose another --out", o.out));
  auto generator = make_generator(o.generator);
  const OutputLock lock(o.out, "--out " + o.out);

  auto ls = load(o.scene, o.common.tracer);
  Accumulator acc(o.common.width, o.common.height);
  const std::string timing =
      on_device(o.common.device) ? render_device(o, *ls, *generator, acc) : render_cpu(o, *ls, *generator, acc);
  const Image image = acc.mean();
  const ToneMap tm = resolved(o.common.tone_map, image);
  write_image(image, o.out, tm);
  const std::string ext = fs::path(o.out).extension().string();
  for (size_t i = 0; i < o.crops.size(); ++i) {
    const std::string path = fmt::format("{}-crop{}{}", stem_path(o.out), i, ext);
    write_image(crop(image, o.crops[i]), path, tm);
    std::printf("crop %d,%d,%d,%d -> %s\n", o.crops[i].x, o.crops[i].y, o.crops[i].w, o.crops[i].h, path.c_str());
  }
  // --device cuda traces every batch with the device trace kernel (BVH2), not with --tracer.
  const std::string tracer =
      on_device(o.common.device)
          ? fmt::format("device trace kernel [bvh=bvh2{}]", fused_device(o.common.device) ? ", first bounce fused" : "")
          : fmt::format("{} [{}]", o.common.tracer.name, ls->tracer->params());
  std::printf("%s, %s [%s], tracer %s: %d frames of %dx%d, seed %u, max depth %d\n", ls->scene.name.c_str(),
              o.generator.name.c_str(), generator->params().c_str(), tracer.c_str(), o.frames, o.common.width,
              o.common.height, o.common.seed, o.common.max_depth);
  std::printf("%s\n", timing.c_str());
  if (acc.non_finite_samples() > 0)
    std::printf("warning: %llu NaN/Inf frame samples in %llu pixels were left out of the image (counted, not added)\n",
                static_cast<unsigned long long>(acc.non_finite_samples()),
                static_cast<unsigned long long>(acc.pixels_with_non_finite()));
  else
    std::printf("NaN/Inf frame samples: 0\n");
  std::printf("wrote %s (%s)\n", o.out.c_str(), provenance.git_revision.c_str());
  return 0;
}

BoundCommand bind_render(CLI::App& parent) {
  struct State {
    RenderOptions o;
    RenderText text;
    std::string generator;
  };
  auto s = std::make_shared<State>();
  s->generator = s->o.generator.text();
  CLI::App* cmd =
      parent.add_subcommand("render", "path-trace a scene with a generator's first bounce; write EXR/PNG/PFM");
  cmd->add_option("--scene", s->o.scene, "scene")->capture_default_str();
  cmd->add_option("--generator", s->generator, "generator of the first bounce")->capture_default_str();
  cmd->add_option("--frames", s->o.frames, "frames to accumulate")->capture_default_str();
  cmd->add_option("--out", s->o.out, "image file (.exr, .png, .pfm)")->capture_default_str();
  cmd->add_option("--crop", s->text.crops, "x,y,w,h region also written on its own (repeatable)");
  bind_render_common(cmd, s->o.common, s->text);
  return {cmd, [s](const Provenance& provenance) {
            resolve_render_common(s->o.common, s->text);
            s->o.generator = parse_plugin_spec(s->generator);
            s->o.crops = parse_crops(s->text.crops);
            return run_render(s->o, provenance);
          }};
}

}  // namespace raycoh
