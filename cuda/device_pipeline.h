// The `cuda` tracer's device pipeline (tracers/device_pipeline.h): a `cuda` run with pipeline=device (the default)
// makes every batch on the GPU and never traces a host-made one. Plain C++ (g++), over the device APIs of
// cuda/device_generators.h (primary rays, noopt / ours / contiguous), cuda/device_keys.h (every key encoder's
// typed KeyRecipe, CUB radix sort), cuda/device_stages.h (the gather of every batch array, buffers, timers) and
// cuda/trace_kernels.h (the trace kernels).
//
// One frame: primary() makes the camera rays in tile order on the device and traces them (its stages: camera rays
// as gen_ms, their trace as trace_ms; the G-buffer is in neither); first_hits_gbuffer() makes their G-buffer on the
// device (cuda/device_gbuffer.h: make_gbuffer's hit_surface per hit, equal to it bit for bit; not timed) and keeps
// it there for the generator (only its hit count is read back; download_gbuffer copies it for tests and checks).
// Each secondary() then queues generation, keys, sort, gather (physical mode) and trace on the default stream
// without a host round trip between the stages, each between its own pair of CUDA events, and one more pair
// around them all (span_ms); only then does it wait and read the times. The device versions equal the CPU's bit
// for bit (tests/gpu_generators_test.cpp, gpu_keys_test.cpp, gpu_pipeline_test.cpp, gpu_gbuffer_test.cpp), so its
// G-buffer, batches, order and hits are the host pipeline's (reis and costa keys aside, where CUDA's atan2f /
// acosf may round a direction bit differently from glibc's: cuda/device_keys.h).
//
// What has no device version is refused, never run on the CPU in its place (device_pipeline_refusal): the
// generator direct (ours / contiguous in scanline order with pipeline=fused), ours / contiguous tiles of more than 1024
// pixels, and the `window` encoder. `cuda:pipeline=host` traces host-made batches instead (the batches every other
// tracer traces).
//
// `cuda:pipeline=fused` (PipelineTrace::fused): a secondary pass is one kernel that makes each tile's rays from
// the G-buffer and traces them where they are made (every device generator, ours and contiguous in tile or group order;
// no encoder with keys). Its time is the pass's trace_ms (generation included; gen_ms is 0). download_secondary then
// gives the batch made again by the materialized generator (the fused pass keeps none) and the fused hits in its order,
// hits[i] = the hit the fused kernel wrote at ray i's pixel.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/warp_counters.h"
#include "cuda/trace_kernels.h"
#include "tracers/device_pipeline.h"

namespace raycoh {
struct Scene;
struct Bvh;
}  // namespace raycoh

namespace raycoh::cuda {

// How the pipeline's trace stage runs: the timing kernel of `launch`, or (counting) the counting kernel, whose
// warps go to `counted` with the batch's ray count.
struct PipelineTrace {
  DeviceTracer* tracer = nullptr;  // the cuda tracer's; outlives the pipeline
  TraceLaunch launch;
  bool counting = false;
  // cuda:pipeline=fused: secondary passes make and trace each tile's rays in one kernel (cuda/fused_kernels.cu);
  // no batch, keys or sort (an encoder with keys is refused).
  bool fused = false;
  SimtConfig layout;  // counting: simt's address layout (simt_config)
  std::function<void(const std::vector<WarpStepCounters>& warps, size_t rays)> counted;
};

// Empty when the generator (named generator_name) and the encoder have device versions (fused: a fused form);
// otherwise one line that names what has none and lists what is valid. Needs no device.
std::string device_pipeline_refusal(const std::string& generator_name, const Generator& generator,
                                    const Encoder& encoder, bool fused = false);

// The Scene and Bvh must outlive the pipeline (mlhcc's cuts are built from the BVH when first asked for).
std::unique_ptr<DevicePipeline> make_device_pipeline(const Scene& scene, const Bvh& bvh, PipelineTrace trace);

}  // namespace raycoh::cuda
