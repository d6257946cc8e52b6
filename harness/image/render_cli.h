// The options the rendering commands bind alike (CLI11 included here, never in the commands' public headers):
// --tracer, --device, --res, --seed, --max-depth, --rr-depth, --tone-map, --exposure, --force, --crop, --protocol,
// --metrics, --reference and durations. They only convert text to values; range checks are the runners' (check_common
// in render_common.h).
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "harness/image/render_options.h"
#include "shading/image.h"

namespace raycoh {

// --tracer, --device, --res, --seed, --max-depth, --rr-depth, --tone-map, --exposure of the rendering commands.
struct RenderText {
  std::string tracer, res, tone_map, exposure;  // defaults from RenderCommon
  std::vector<std::string> crops;
};
void bind_render_common(CLI::App* cmd, RenderCommon& c, RenderText& text);
void resolve_render_common(RenderCommon& c, const RenderText& text);
std::vector<Crop> parse_crops(const std::vector<std::string>& texts);

// --protocol ci|paper (and --metrics tonemapped|linear where `metrics`) of quality, converge and reference. After
// resolve_render_common, resolve_protocol applies the protocol to every option not given on the command line
// (render_options.h apply_protocol).
struct ProtocolText {
  std::string protocol = "ci", metrics;
};
void bind_protocol(CLI::App* cmd, ProtocolText& text, bool metrics);
void resolve_protocol(CLI::App* cmd, const ProtocolText& text, RenderCommon& c, int* frames, const char* frames_option,
                      int* ref_frames, const char* ref_option);
// --reference FILE of quality and converge: when FILE's cache sidecar gives its frame count (shading/reference.h
// reference_file_frames), *ref_frames becomes that count; an explicit --ref-frames that differs is refused. Returns
// false when the count is unknown (a file without its sidecar), true otherwise (also without --reference).
bool adopt_reference_frames(CLI::App* cmd, const std::string& reference, int* ref_frames);

// "60s", "1.5m", "500ms", "2h" or a plain number of seconds (--time of converge); throws raycoh::Error naming
// `what` unless finite and > 0.
double parse_duration(const std::string& what, const std::string& text);

}  // namespace raycoh
