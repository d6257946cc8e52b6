// raycoh command line: list, scenes info, table, rays. User errors print one line and exit with code 2.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <fmt/format.h>
#include <tbb/global_control.h>
#include <thread>

#include "core/error.h"
#include "harness/commands.h"
#if defined(RAYCOH_HAVE_CUDA)
#include "cuda/cuda_trace.h"
#endif
#include "harness/quality.h"
#include "harness/table.h"

namespace {

using namespace raycoh;

std::vector<std::string> split_scenes(const std::string& text) {
  std::vector<std::string> out;
  for (const PluginSpec& s : split_plugin_list(text)) out.push_back(s.text());
  if (out.empty()) throw Error("--scenes: empty list");
  return out;
}

std::vector<PluginSpec> split_nonempty(const std::string& option, const std::string& text) {
  auto list = split_plugin_list(text);
  if (list.empty()) throw Error(fmt::format("{}: empty list", option));
  return list;
}

// `auto`: the GPU tracer where a CUDA device exists, else the CPU tracer and the SIMT/cache model.
std::vector<PluginSpec> expand_auto(const std::vector<PluginSpec>& tracers) {
  std::vector<PluginSpec> out;
  for (const PluginSpec& t : tracers) {
    if (t.name != "auto") {
      out.push_back(t);
      continue;
    }
    if (!t.params.empty()) throw Error("tracer 'auto' takes no parameters");
#if defined(RAYCOH_HAVE_CUDA)
    if (cuda::device_count() > 0) {
      out.push_back({"cuda", ""});
      continue;
    }
#endif
    out.push_back({"cpu", ""});
    out.push_back({"simt", ""});
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"raycoh: which way of making secondary rays coherent pays off, on which scene, at what cost"};
  app.require_subcommand(1);
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  app.add_option("--threads", threads, "worker threads (default: all cores)")->check(CLI::Range(1, 1024));

  app.add_subcommand("list", "list generators, encoders, tracers and built-in scenes with their parameters");

  auto* scenes_cmd = app.add_subcommand("scenes", "scene utilities");
  scenes_cmd->require_subcommand(1);
  std::string info_scene;
  auto* info_cmd = scenes_cmd->add_subcommand("info", "print a scene's features, the stages it skips, its BVH");
  info_cmd->add_option("scene", info_scene, "built-in name or .gltf/.glb/.obj path")->required();

  TableOptions table;
  std::string t_scenes = "cornell,voxels", t_generators = "noopt", t_tracers = "cpu,embree", t_res = "320x240";
  auto* table_cmd = app.add_subcommand("table", "trace primary and secondary rays; print MRay/s and ratios to NoOpt");
  table_cmd->add_option("--scenes", t_scenes, "comma-separated scenes (built-in names, files or folders)")
      ->capture_default_str();
  table_cmd->add_option("--generators", t_generators, "comma-separated generators, e.g. noopt")->capture_default_str();
  table_cmd->add_option("--tracers", t_tracers, "comma-separated tracers, e.g. cpu,embree:mode=packet16,simt; auto = cuda with a GPU, else cpu,simt")
      ->capture_default_str();
  std::string t_encoders = "none";
  table_cmd->add_option("--encoders", t_encoders, "comma-separated reordering encoders, applied to every generator")
      ->capture_default_str();
  table_cmd->add_option("--permute", table.permute, "how a reordering is applied: physical or indirect")
      ->capture_default_str();
  table_cmd->add_option("--res", t_res, "resolution WxH")->capture_default_str();
  table_cmd->add_option("--frames", table.frames, "frames per scene")->check(CLI::Range(1, 100000))->capture_default_str();
  table_cmd->add_option("--seed", table.seed, "random seed")->capture_default_str();
  table_cmd->add_option("--repeat", table.repeats, "timed traces per batch (median reported)")
      ->check(CLI::Range(1, 1000))->capture_default_str();
  table_cmd->add_option("--out", table.out, "CSV file to write")->capture_default_str();

  SweepOptions sweep;
  std::string s_tiles = "8x8,16x8,16x16,32x8", s_groups = "8,16,32,64", s_tracers = "cpu", s_res = "320x240";
  auto* sweep_cmd = app.add_subcommand("sweep", "tile size x group size of ours (the paper's Table 3 layout)");
  sweep_cmd->add_option("--scene", sweep.scene, "scene")->required();
  sweep_cmd->add_option("--generator", sweep.generator, "ours or tile")->capture_default_str();
  sweep_cmd->add_option("--tiles", s_tiles, "comma-separated tile sizes WxH")->capture_default_str();
  sweep_cmd->add_option("--groups", s_groups, "comma-separated group sizes K")->capture_default_str();
  sweep_cmd->add_option("--tracers", s_tracers, "comma-separated tracers")->capture_default_str();
  sweep_cmd->add_option("--res", s_res, "resolution WxH")->capture_default_str();
  sweep_cmd->add_option("--frames", sweep.frames, "frames")->check(CLI::Range(1, 100000))->capture_default_str();
  sweep_cmd->add_option("--seed", sweep.seed, "random seed")->capture_default_str();
  sweep_cmd->add_option("--repeat", sweep.repeats, "timed traces per batch (median reported)")
      ->check(CLI::Range(1, 1000))->capture_default_str();
  sweep_cmd->add_option("--out", sweep.out, "CSV file to write")->capture_default_str();

  // Options every rendering command shares (RenderCommon), bound to a subcommand.
  struct CommonText {
    std::string tracer = "cpu", res = "160x120", tone_map = "aces", exposure = "auto";
    std::vector<std::string> crops;
  };
  auto add_common = [](CLI::App* cmd, RenderCommon& c, CommonText& t) {
    cmd->add_option("--tracer", t.tracer, "tracer of every bounce (cpu or embree)")->capture_default_str();
    cmd->add_option("--res", t.res, "resolution WxH")->capture_default_str();
    cmd->add_option("--seed", c.seed, "random seed")->capture_default_str();
    cmd->add_option("--max-depth", c.max_depth, "scattering events per path")->check(CLI::Range(1, 64))
        ->capture_default_str();
    cmd->add_option("--rr-depth", c.rr_depth, "Russian roulette from this bounce on")->check(CLI::Range(1, 64))
        ->capture_default_str();
    cmd->add_option("--tone-map", t.tone_map, "aces or clamp (PNG output, PSNR and SSIM)")->capture_default_str();
    cmd->add_option("--exposure", t.exposure, "auto (0.18 / log-average luminance of the reference) or a number")
        ->capture_default_str();
  };
  auto resolve_common = [](RenderCommon& c, const CommonText& t) {
    c.tracer = parse_plugin_spec(t.tracer);
    std::tie(c.width, c.height) = parse_size("--res", t.res, 1, 16384);
    c.tone_map.kind = parse_tone_map(t.tone_map);
    c.tone_map.auto_exposure = t.exposure == "auto";
    if (!c.tone_map.auto_exposure) {
      char* end = nullptr;
      c.tone_map.exposure = std::strtof(t.exposure.c_str(), &end);
      if (t.exposure.empty() || *end != '\0' || !(c.tone_map.exposure > 0.f) || !std::isfinite(c.tone_map.exposure))
        throw Error("--exposure: '" + t.exposure + "' is not valid; expected auto or a positive number");
    }
  };
  auto parse_crops = [](const std::vector<std::string>& texts) {
    std::vector<Crop> crops;
    for (const std::string& t : texts) crops.push_back(parse_crop("--crop", t));
    return crops;
  };

  RenderOptions render;
  CommonText render_text;
  std::string render_generator = "noopt";
  auto* render_cmd = app.add_subcommand("render", "path-trace a scene with a generator's first bounce; write EXR/PNG/PFM");
  render_cmd->add_option("--scene", render.scene, "scene")->capture_default_str();
  render_cmd->add_option("--generator", render_generator, "generator of the first bounce")->capture_default_str();
  render_cmd->add_option("--frames", render.frames, "frames to accumulate")->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  render_cmd->add_option("--out", render.out, "image file (.exr, .png, .pfm)")->capture_default_str();
  render_cmd->add_option("--crop", render_text.crops, "x,y,w,h region also written on its own (repeatable)");
  add_common(render_cmd, render.common, render_text);

  QualityOptions quality;
  CommonText quality_text;
  std::string q_scenes = "cornell", q_generators = "noopt,ours";
  auto* quality_cmd = app.add_subcommand("quality", "image error of each generator against a NoOpt reference (Table 2)");
  quality_cmd->add_option("--scenes", q_scenes, "comma-separated scenes")->capture_default_str();
  quality_cmd->add_option("--generators", q_generators, "comma-separated generators")->capture_default_str();
  quality_cmd->add_option("--frames", quality.frames, "frames per render")->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  quality_cmd->add_option("--ref-frames", quality.ref_frames, "NoOpt frames of the reference")
      ->check(CLI::Range(1, 1 << 20))->capture_default_str();
  quality_cmd->add_option("--bias-renders", quality.bias_renders, "independent renders per generator")
      ->check(CLI::Range(1, 256))->capture_default_str();
  quality_cmd->add_option("--cache", quality.cache_dir, "reference cache folder (default $RAYCOH_CACHE or results/cache)");
  quality_cmd->add_option("--reference", quality.reference, "use this .exr/.pfm as the reference (one scene)");
  quality_cmd->add_option("--out", quality.out, "CSV file to write")->capture_default_str();
  quality_cmd->add_option("--images", quality.image_dir, "folder for renders and crops (default <out stem>-images)");
  quality_cmd->add_option("--crop", quality_text.crops, "x,y,w,h hotspot region written per render (repeatable)");
  add_common(quality_cmd, quality.common, quality_text);

  ConvergeOptions converge;
  CommonText converge_text;
  std::string c_generators = "noopt,ours", c_time = "10s";
  auto* converge_cmd = app.add_subcommand("converge", "error against wall-clock and trace time; equal-time and "
                                                      "equal-error ratios");
  converge_cmd->add_option("--scene", converge.scene, "scene")->capture_default_str();
  converge_cmd->add_option("--generators", c_generators, "comma-separated generators, the first is the baseline")
      ->capture_default_str();
  converge_cmd->add_option("--time", c_time, "render time per generator (60s, 1.5m, 500ms)")->capture_default_str();
  converge_cmd->add_option("--max-frames", converge.max_frames, "stop a generator after this many frames")
      ->check(CLI::Range(1, 1 << 20));
  converge_cmd->add_option("--ref-frames", converge.ref_frames, "NoOpt frames of the reference")
      ->check(CLI::Range(1, 1 << 20))->capture_default_str();
  converge_cmd->add_option("--cache", converge.cache_dir, "reference cache folder");
  converge_cmd->add_option("--reference", converge.reference, "use this .exr/.pfm as the reference");
  converge_cmd->add_option("--out", converge.out, "CSV file to write")->capture_default_str();
  add_common(converge_cmd, converge.common, converge_text);

  CompareOptions compare;
  auto* compare_cmd = app.add_subcommand("compare", "every error metric between two image files");
  compare_cmd->add_option("test", compare.test, "image to measure (.exr or .pfm)")->required();
  compare_cmd->add_option("reference", compare.reference, "reference image (.exr or .pfm)")->required();

  RaysOptions rays;
  std::string r_generator = "noopt", r_res = "320x240";
  auto* rays_cmd = app.add_subcommand("rays", "dump one frame's secondary ray batch as CSV, one row per ray");
  rays_cmd->add_option("--scene", rays.scene, "scene")->required();
  rays_cmd->add_option("--generator", r_generator, "generator")->capture_default_str();
  std::string r_encoder = "none";
  rays_cmd->add_option("--encoder", r_encoder, "encoder whose key is written per ray (hex)")->capture_default_str();
  rays_cmd->add_option("--frame", rays.frame, "frame index")->check(CLI::Range(0, 1 << 30))->capture_default_str();
  rays_cmd->add_option("--res", r_res, "resolution WxH")->capture_default_str();
  rays_cmd->add_option("--seed", rays.seed, "random seed")->capture_default_str();
  rays_cmd->add_option("--out", rays.out, "CSV file to write")->required();

  std::vector<std::string> commands;
  for (const CLI::App* sub : app.get_subcommands({})) commands.push_back(sub->get_name());
  for (int i = 1; i < argc; ++i) {  // the first word that is not an option must be a command
    const std::string arg = argv[i];
    if (arg.rfind("-", 0) == 0) {
      if (arg == "--threads") ++i;
      continue;
    }
    if (std::find(commands.begin(), commands.end(), arg) == commands.end()) {
      std::fprintf(stderr, "raycoh: error: unknown command '%s'; valid commands: %s\n", arg.c_str(),
                   join(commands).c_str());
      return 2;
    }
    break;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "raycoh: error: %s (see raycoh --help)\n", e.what());
    return 2;
  }

  tbb::global_control threads_control(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
  const Provenance provenance = collect_provenance(argc, argv, threads);
  try {
    if (app.got_subcommand("list")) {
      run_list();
    } else if (info_cmd->parsed()) {
      run_scene_info(info_scene);
    } else if (table_cmd->parsed()) {
      table.scenes = split_scenes(t_scenes);
      table.generators = split_nonempty("--generators", t_generators);
      table.tracers = expand_auto(split_nonempty("--tracers", t_tracers));
      table.encoders = split_nonempty("--encoders", t_encoders);
      std::tie(table.width, table.height) = parse_size("--res", t_res, 1, 16384);
      return run_table(table, provenance);
    } else if (sweep_cmd->parsed()) {
      sweep.tiles.clear();
      for (const PluginSpec& t : split_nonempty("--tiles", s_tiles))
        sweep.tiles.push_back(parse_size("--tiles", t.text(), 1, 1024));
      sweep.groups.clear();
      for (const PluginSpec& k : split_nonempty("--groups", s_groups))
        sweep.groups.push_back(parse_int("--groups", k.text(), 1, 65536));
      sweep.tracers = expand_auto(split_nonempty("--tracers", s_tracers));
      std::tie(sweep.width, sweep.height) = parse_size("--res", s_res, 1, 16384);
      return run_sweep(sweep, provenance);
    } else if (render_cmd->parsed()) {
      resolve_common(render.common, render_text);
      render.generator = parse_plugin_spec(render_generator);
      render.crops = parse_crops(render_text.crops);
      return run_render(render, provenance);
    } else if (quality_cmd->parsed()) {
      resolve_common(quality.common, quality_text);
      quality.scenes = split_scenes(q_scenes);
      quality.generators = split_nonempty("--generators", q_generators);
      quality.crops = parse_crops(quality_text.crops);
      return run_quality(quality, provenance);
    } else if (converge_cmd->parsed()) {
      resolve_common(converge.common, converge_text);
      converge.generators = split_nonempty("--generators", c_generators);
      converge.time_s = parse_duration("--time", c_time);
      return run_converge(converge, provenance);
    } else if (compare_cmd->parsed()) {
      return run_compare(compare);
    } else if (rays_cmd->parsed()) {
      rays.generator = parse_plugin_spec(r_generator);
      rays.encoder = parse_plugin_spec(r_encoder);
      std::tie(rays.width, rays.height) = parse_size("--res", r_res, 1, 16384);
      run_rays(rays, provenance);
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "raycoh: error: %s\n", e.what());
    return 2;
  }
  return 0;
}
