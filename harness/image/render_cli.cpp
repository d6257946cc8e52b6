#include "harness/image/render_cli.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <tuple>

#include "core/error.h"
#include "harness/common/cli.h"
#include "shading/reference.h"

namespace raycoh {

void bind_render_common(CLI::App* cmd, RenderCommon& c, RenderText& t) {
  t.tracer = c.tracer.text();
  t.res = fmt::format("{}x{}", c.width, c.height);
  t.tone_map = c.tone_map.kind == ToneMapKind::Aces ? "aces" : "clamp";
  t.exposure = c.tone_map.auto_exposure ? "auto" : fmt::format("{}", c.tone_map.exposure);
  cmd->add_option("--tracer", t.tracer, "tracer of every bounce (cpu or embree)")->capture_default_str();
  cmd->add_option("--device", c.device,
                  "cpu; cuda: every frame on the device path tracer (its GPU time labelled measured or simulated); "
                  "cuda:pipeline=fused: the same with its first bounce made and traced in one kernel per tile")
      ->capture_default_str();
  cmd->add_option("--res", t.res, "resolution WxH")->capture_default_str();
  cmd->add_option("--seed", c.seed, "random seed")->capture_default_str();
  cmd->add_option("--max-depth", c.max_depth, "scattering events per path")->capture_default_str();
  cmd->add_option("--rr-depth", c.rr_depth, "Russian roulette from this bounce on")->capture_default_str();
  cmd->add_option("--tone-map", t.tone_map, "aces or clamp (PNG output, PSNR and SSIM)")->capture_default_str();
  cmd->add_option("--exposure", t.exposure, "auto (0.18 / log-average luminance of the reference) or a number")
      ->capture_default_str();
  cmd->add_flag("--force", c.force, "replace an existing --out instead of resuming it or refusing");
}

void resolve_render_common(RenderCommon& c, const RenderText& t) {
  c.tracer = parse_plugin_spec(t.tracer);
  std::tie(c.width, c.height) = parse_res("--res", t.res);
  c.tone_map.kind = parse_tone_map(t.tone_map);
  c.tone_map.auto_exposure = t.exposure == "auto";
  if (!c.tone_map.auto_exposure) {
    char* end = nullptr;
    c.tone_map.exposure = std::strtof(t.exposure.c_str(), &end);
    if (t.exposure.empty() || *end != '\0')
      throw Error("--exposure: '" + t.exposure + "' is not valid; expected auto or a positive number");
  }
}

void bind_protocol(CLI::App* cmd, ProtocolText& t, bool metrics) {
  cmd->add_option("--protocol", t.protocol,
                  "ci (160x120, 32 vs 512 frames, tone-mapped metrics) or paper (1920x1080, 128 vs 4096 frames, "
                  "linear metrics); options given alongside replace its values")
      ->capture_default_str();
  if (metrics)
    cmd->add_option("--metrics", t.metrics,
                    "tonemapped or linear: the space of PSNR and SSIM (default: the protocol's)");
}

void resolve_protocol(CLI::App* cmd, const ProtocolText& t, RenderCommon& c, int* frames, const char* frames_option,
                      int* ref_frames, const char* ref_option) {
  apply_protocol(
      protocol_named("--protocol", t.protocol),
      [cmd](const std::string& o) {
        const CLI::Option* opt = cmd->get_option_no_throw(o);
        return opt && opt->count() > 0;
      },
      c, frames, frames_option, ref_frames, ref_option);
  if (!t.metrics.empty()) c.metrics = parse_metric_space("--metrics", t.metrics);
}

bool adopt_reference_frames(CLI::App* cmd, const std::string& reference, int* ref_frames) {
  if (reference.empty()) return true;
  const int n = reference_file_frames(reference);
  if (n == 0) return false;
  const CLI::Option* opt = cmd->get_option_no_throw("--ref-frames");
  if (opt && opt->count() > 0 && *ref_frames != n)
    throw Error(
        fmt::format("--reference {}: it holds {} frames (its cache sidecar says so) but --ref-frames is {}; "
                    "leave --ref-frames out or give {}",
                    reference, n, *ref_frames, n));
  *ref_frames = n;
  return true;
}

std::vector<Crop> parse_crops(const std::vector<std::string>& texts) {
  std::vector<Crop> crops;
  for (size_t i = 0; i < texts.size(); ++i) {
    for (size_t j = 0; j < i; ++j)
      if (texts[i] == texts[j]) throw Error(fmt::format("--crop {}: given twice; name each crop once", texts[i]));
    crops.push_back(parse_crop("--crop", texts[i]));
  }
  return crops;
}

double parse_duration(const std::string& what, const std::string& text) {
  size_t end = 0;
  double v = std::nan("");
  try {
    v = std::stod(text, &end);
  } catch (const std::exception&) {
    end = 0;
  }
  const std::string unit = end > 0 ? text.substr(end) : std::string();
  double scale = 0;
  if (unit.empty() || unit == "s")
    scale = 1;
  else if (unit == "ms")
    scale = 1e-3;
  else if (unit == "m" || unit == "min")
    scale = 60;
  else if (unit == "h")
    scale = 3600;
  if (end == 0 || scale == 0)
    throw Error(fmt::format("{} '{}': expected a duration such as 60s, 1.5m, 500ms or 2h", what, text));
  v *= scale;
  if (!(v > 0) || !std::isfinite(v) || v > 1e6)
    throw Error(fmt::format("{} '{}': must be more than 0 and at most 1e6 seconds", what, text));
  return v;
}

}  // namespace raycoh
