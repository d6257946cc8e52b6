// The measured columns of a tracer that runs the whole pipeline on its device (tracers/device_pipeline.h: `cuda`
// with pipeline=device). Its passes time themselves with CUDA events; here they are repeated like every timing
// tracer's traces and written into the row (results/README.md, the `pipeline` column).
#pragma once

#include <functional>
#include <vector>

#include "encoders/encoder.h"
#include "records/experiment_row.h"
#include "tracers/device_pipeline.h"

namespace raycoh {

struct DeviceMeasurement {
  DeviceStageTimes median;               // each stage's median over the timed passes
  double trace_min_ms = 0;               // the fastest trace
  std::vector<DeviceStageTimes> passes;  // every timed pass, in order
};

// Timing runs: one untimed pass (buffers grown, kernels loaded), then `repeats` timed passes. Counting runs
// (counting = true: the trace is the counting kernel, deterministic): one pass.
DeviceMeasurement measure_device(const std::function<DeviceStageTimes()>& pass, int repeats, bool counting);

// pipeline = device and the measured GPU times: gen_ms, key_ms, sort_ms, permute_ms, trace_ms (+ trace_ms_min),
// mray_s, e2e_ms = the sum of the stages and e2e_mray_s; for timing runs also gpu_e2e_ms (the measured span) and
// gpu_e2e_mray_s, and from two timed passes on the intervals and every pass's trace and end to end (the span)
// (harness/speed/repeat_timing.h). row.rays must be set.
void set_device_times(ExperimentRow& row, const DeviceMeasurement& m, bool counting);

// The bytes the last secondary pass of `pipeline` moved in each stage (simt/pipeline_model.h stage_traffic; the
// gather's by the pass's own sort order, downloaded untimed): modeled_*_bytes, the traffic a measured stage is
// set beside. row.rays must be set.
void set_stage_traffic(ExperimentRow& row, const DevicePipeline& pipeline, const Encoder& encoder, PermuteMode mode,
                       size_t pixels, bool fused);

}  // namespace raycoh
