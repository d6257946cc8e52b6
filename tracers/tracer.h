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

namespace raycoh {

struct Scene;
struct Bvh;

// What the `simt` tracer measures over one batch (every rule in simt/simt.h; the cache model in
// simt/cache_model.h). All fields but modeled_cost are exact integer sums, the same for every thread count.
// A CUDA counting run that follows simt/simt.h reproduces everything above the cache-model block exactly.
struct CoherenceCounters {
  uint64_t rays = 0;   // rays in the batch
  uint64_t warps = 0;  // ceil(rays / warp_size); the last one may be partial
  uint32_t warp_size = 32;
  uint32_t line_bytes = 64;    // line size of the *_lines transactions
  uint32_t sector_bytes = 32;  // sector size of the cache model and of *_fetches

  // Warp steps: iterations of the warp's node loop, of its leaf loop, and triangle iterations inside leaf steps;
  // then the active lanes summed over each kind of step.
  uint64_t node_steps = 0, leaf_steps = 0, triangle_steps = 0;
  uint64_t node_lanes = 0, leaf_lanes = 0, triangle_lanes = 0;
  // Memory transactions: distinct line_bytes lines among the active lanes' fetches, summed over steps.
  uint64_t node_lines = 0, triangle_lines = 0;
  // Cache-model requests: distinct sector_bytes sectors among the active lanes' fetches, summed over steps
  // (= L1 accesses).
  uint64_t node_fetches = 0, triangle_fetches = 0;
  // Per-ray totals (RayCounters summed over the rays). Equal to the *_lanes sums by construction.
  uint64_t nodes = 0, leaves = 0, triangles = 0;

  // Cache model, in sectors.
  uint64_t l1_hits = 0, l1_misses = 0;
  uint64_t l2_hits = 0, l2_misses = 0;
  uint64_t dram_bytes = 0;    // l2_misses x sector_bytes
  double modeled_cost = 0.0;  // cycles, whole batch (simt/simt.h, modeled_cost())

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
  double cost_per_ray() const { return per_ray(modeled_cost); }

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
  // Counters of the last trace() call, for tracers that model coherence (`simt`); nullptr for the others.
  virtual const CoherenceCounters* last_counters() const { return nullptr; }
  // Device time of the last trace() / trace_indirect() call in milliseconds (the kernel alone, from CUDA events),
  // for tracers that run on a GPU (`cuda`); -1 for host tracers, whose caller times the call itself.
  virtual double last_device_ms() const { return -1.0; }
};

// Reads its values from a ParamSet over the record's table; throws raycoh::Error for bad ones. The Scene and Bvh
// must outlive the tracer.
using TracerFactory = std::unique_ptr<Tracer> (*)(ParamSet& params, const Scene& scene, const Bvh& bvh);
using TracerInfo = PluginInfo<TracerFactory>;

// The explicit registry (adding a tracer = one file + one record in tracers/registry.cpp).
const std::vector<TracerInfo>& tracer_infos();
// Throws raycoh::Error for unknown names or bad parameters, naming the valid choices.
std::unique_ptr<Tracer> make_tracer(const PluginSpec& spec, const Scene& scene, const Bvh& bvh);

}  // namespace raycoh
