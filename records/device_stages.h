// The device path tracer's frame cut by stage (cuda/device_path_tracer.h DeviceFrameStages: CUDA events on its one
// stream, in ms), as the rows that carry it record it: `converge` per frame. NaN (an empty cell) on the CPU and in
// rows written before the columns. The stages add up to at most the frame's own GPU time (frame_gpu_ms). Beside
// them, the trace kernels of the first and second bounces' waves (parts of `trace`) with their rays: each
// bounce's measured trace speed, to see whether the first bounce's coherence carries into the second.
#pragma once

#include <cmath>

#include "records/schema.h"

namespace raycoh {

struct DeviceStageMs {
  double camera = std::nan("");      // camera rays, the G-buffer kernel and its hit count, camera shading
  double generation = std::nan("");  // the first bounce's batch by the device generator
  double next_event = std::nan("");  // shadow rays made, resolved and added (not their traces)
  double sample = std::nan("");      // bounce sampling of the later bounces
  double trace = std::nan("");       // every trace kernel: camera rays, shadow rounds, waves
  double gather = std::nan("");      // each wave's hits shaded, light added, next vertices compacted
  // Of `trace`: the first bounce's wave (fused: the kernel that makes and traces it) and the second's, and their
  // rays (counts, held as numbers so that an empty cell reads as NaN).
  double first_trace = std::nan(""), second_trace = std::nan("");
  double first_rays = std::nan(""), second_rays = std::nan("");
};

// f(name, ms) for each stage in the frame's order (names as in the columns, without gpu_ and _ms).
template <class F>
void for_each_stage(const DeviceStageMs& s, F&& f) {
  f("camera", s.camera), f("generation", s.generation), f("next_event", s.next_event), f("sample", s.sample),
      f("trace", s.trace), f("gather", s.gather);
}

// sum += frame, field by field (a NaN in sum counts as 0: a sum starts at DeviceStageMs{}).
inline void add_stages(DeviceStageMs& sum, const DeviceStageMs& frame) {
  auto add = [](double& a, double b) { a = (std::isnan(a) ? 0.0 : a) + b; };
  add(sum.camera, frame.camera), add(sum.generation, frame.generation), add(sum.next_event, frame.next_event);
  add(sum.sample, frame.sample), add(sum.trace, frame.trace), add(sum.gather, frame.gather);
  add(sum.first_trace, frame.first_trace), add(sum.second_trace, frame.second_trace);
  add(sum.first_rays, frame.first_rays), add(sum.second_rays, frame.second_rays);
}

// Columns gpu_camera_ms, gpu_generation_ms, gpu_next_event_ms, gpu_sample_ms, gpu_trace_ms, gpu_gather_ms,
// gpu_first_trace_ms, gpu_second_trace_ms, first_wave_rays, second_wave_rays.
const Schema<DeviceStageMs>& device_stage_schema();

}  // namespace raycoh
