#include "records/device_stages.h"

namespace raycoh {

const Schema<DeviceStageMs>& device_stage_schema() {
  using namespace csv_format;
  using S = DeviceStageMs;
  using G = GeneralOrEmpty;
  static const Schema<S> schema = {
      column("gpu_camera_ms", &S::camera, G{}),
      column("gpu_generation_ms", &S::generation, G{}),
      column("gpu_next_event_ms", &S::next_event, G{}),
      column("gpu_sample_ms", &S::sample, G{}),
      column("gpu_trace_ms", &S::trace, G{}),
      column("gpu_gather_ms", &S::gather, G{}),
      column("gpu_first_trace_ms", &S::first_trace, G{}),
      column("gpu_second_trace_ms", &S::second_trace, G{}),
      column("first_wave_rays", &S::first_rays, G{}),
      column("second_wave_rays", &S::second_rays, G{}),
  };
  return schema;
}

}  // namespace raycoh
