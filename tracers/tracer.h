// The tracer interface: one virtual call per batch, never per ray. A tracer is made for one scene (it may build
// acceleration structures of its own in the constructor, which is not part of the timed trace) and then traces
// any number of batches of closest-hit rays.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/params.h"
#include "core/plugin.h"
#include "core/ray.h"
#include "core/warp_counters.h"

namespace raycoh {

struct Scene;
struct Bvh;
struct GpuModelConfig;
class DevicePipeline;

// The modeled time of one trace kernel on the `simt` tracer's GPU preset (simt/timed_replay.h). Modeled, not
// measured: never added to a measured time. Busy figures are the time a port was occupied (per-SM ports: the
// busiest SM); one close to `cycles` names the limiter.
struct ModeledKernel {
  double cycles = 0;                                               // kernel time in SM cycles
  double ms = 0;                                                   // kernel time
  uint32_t resident_warps = 0;                                     // per SM
  double issue_busy = 0, l1_busy = 0, l2_busy = 0, dram_busy = 0;  // cycles
  double tail_cycles = 0;    // from the first slot left without work to the end of the kernel
  uint64_t ray_sectors = 0;  // ray-fetch sectors (the cache counters below count the BVH's only)
  uint64_t ray_dram_sectors = 0;
  double issue_cycles = 0;  // partition issue cycles of all warp steps
  // Wavefronts through the L1 pipeline, all SMs (one per cycle per SM): every memory instruction's, and of them
  // the local-memory ones (the traversal stack and state, one per access). Beside a GPU's counted wavefronts.
  double l1_wavefronts = 0, l1_local_wavefronts = 0;
};

// What the `simt` tracer measures over one batch (every rule in simt/simt.h; the cache model in
// simt/cache_model.h, the timing model in simt/timed_replay.h). All fields but `modeled` are exact integer sums;
// every field is the same for every thread count.
// A CUDA counting run that follows simt/simt.h reproduces everything above the cache-model block exactly.
struct CoherenceCounters : WarpStepCounters {
  uint32_t warp_size = 32;
  uint32_t line_bytes = 64;    // line size of the *_lines transactions
  uint32_t sector_bytes = 32;  // sector size of the cache model and of *_fetches

  // Cache model, in sectors.
  uint64_t l1_hits = 0, l1_misses = 0;
  uint64_t l2_hits = 0, l2_misses = 0;
  uint64_t dram_bytes = 0;  // l2_misses x sector_bytes
  // The timing model's kernel time (zero where no model ran, e.g. CUDA counting runs).
  ModeledKernel modeled;

  // Fraction of lanes doing useful work: active lanes / (warp_size x steps). Node and leaf steps pooled.
  double simt_efficiency() const {
    return ratio(static_cast<double>(node_lanes + leaf_lanes),
                 static_cast<double>(warp_size) * static_cast<double>(node_steps + leaf_steps));
  }
  double node_simt_efficiency() const {
    return ratio(static_cast<double>(node_lanes), static_cast<double>(warp_size) * static_cast<double>(node_steps));
  }
  double leaf_simt_efficiency() const {
    return ratio(static_cast<double>(leaf_lanes), static_cast<double>(warp_size) * static_cast<double>(leaf_steps));
  }
  double triangle_simt_efficiency() const {
    return ratio(static_cast<double>(triangle_lanes),
                 static_cast<double>(warp_size) * static_cast<double>(triangle_steps));
  }
  double per_ray(double total) const { return ratio(total, static_cast<double>(rays)); }
  double per_ray(uint64_t total) const { return per_ray(static_cast<double>(total)); }
  double fetches_per_ray() const { return per_ray(node_fetches + triangle_fetches); }
  double lines_per_ray() const { return per_ray(node_lines + triangle_lines); }
  double l1_misses_per_ray() const { return per_ray(l1_misses); }
  double l2_misses_per_ray() const { return per_ray(l2_misses); }
  double dram_bytes_per_ray() const { return per_ray(dram_bytes); }
  double modeled_mray_s() const { return modeled.ms > 0 ? static_cast<double>(rays) / modeled.ms * 1e-3 : 0.0; }

 private:
  static double ratio(double a, double b) { return b > 0.0 ? a / b : 0.0; }
};

class Tracer {
 public:
  virtual ~Tracer() = default;
  // Closest hit of rays[i] into hits[i], for all i < count. Not timed inside: the caller times this call.
  virtual void trace(const Ray* rays, size_t count, Hit* hits) = 0;
  // Indirect fetch through sorted indices: closest hit of rays[order[i]] into hits[i] (lane i of the batch
  // traces ray order[i]). Tracers that cannot fetch indirectly gather the rays first, inside this timed call.
  virtual void trace_indirect(const Ray* rays, const uint32_t* order, size_t count, Hit* hits);
  // Canonical, defaulted parameter set ("mode=single").
  virtual std::string params() const = 0;
  // The acceleration structure it traverses: "bvh2", "cwbvh" (core/cwbvh.h) or "embree" (Embree's own).
  virtual std::string bvh_layout() const { return "bvh2"; }
  // Counters of the last trace() call, for tracers that model coherence (`simt`); nullptr for the others.
  virtual const CoherenceCounters* last_counters() const { return nullptr; }
  // The modelled GPU of tracers that model one (`simt`), for modeling the rest of the pipeline on it.
  virtual const GpuModelConfig* gpu_model() const { return nullptr; }
  // Device time of the last trace() / trace_indirect() call in milliseconds (the kernel alone, from CUDA events),
  // for tracers that run on a GPU (`cuda`); -1 for host tracers, whose caller times the call itself.
  virtual double last_device_ms() const { return -1.0; }
  // The whole per-frame pipeline on this tracer's device (tracers/device_pipeline.h), for tracers that run one
  // (`cuda` with pipeline=device); nullptr for those that trace host-made batches. Owned by the tracer.
  virtual DevicePipeline* device_pipeline() { return nullptr; }
};

// Reads its values from a ParamSet over the record's table; throws raycoh::Error for bad ones. The Scene and Bvh
// must outlive the tracer.
using TracerFactory = std::unique_ptr<Tracer> (*)(ParamSet& params, const Scene& scene, const Bvh& bvh);
// The registry of these records and make_tracer are plugins/tracer_registry.h, above every folder with a tracer.
using TracerInfo = PluginInfo<TracerFactory>;

}  // namespace raycoh
