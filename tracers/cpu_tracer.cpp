// Tracer `cpu`: our own traversal (core/traverse.h, closest_hit with NoCounters) on the shared flat BVH2, run
// over the batch with oneTBB, one task per block of consecutive rays.
//
// Parameters: none (cpu_params() is empty).
//
// Follows Aila & Laine, "Understanding the Efficiency of Ray Traversal on GPUs" (HPG 2009): while-while traversal
// of a two-boxes-per-node BVH2, with the watertight triangle test of Woop, Benthin and Wald (JCGT 2013). Every
// ray is independent, so the hits are the same whatever the thread count or scheduling.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <memory>

#include "bvh/bvh_build.h"
#include "core/flush_denormals.h"
#include "core/traverse.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

// Rays per task: large enough to amortise scheduling, small enough to balance incoherent batches on few cores.
constexpr size_t kRaysPerBlock = 256;

class CpuTracer final : public Tracer {
 public:
  explicit CpuTracer(const Bvh& bvh) : bvh_(bvh.view()) {}

  void trace(const Ray* rays, size_t count, Hit* hits) override {
    const BvhView bvh = bvh_;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kRaysPerBlock), [&](const tbb::blocked_range<size_t>& r) {
      const FlushDenormalsScope ftz;  // same floating-point mode as the Embree tracer, for a fair comparison
      for (size_t i = r.begin(); i != r.end(); ++i) hits[i] = closest_hit(bvh, rays[i]);
    });
  }

  void trace_indirect(const Ray* rays, const uint32_t* order, size_t count, Hit* hits) override {
    const BvhView bvh = bvh_;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kRaysPerBlock), [&](const tbb::blocked_range<size_t>& r) {
      const FlushDenormalsScope ftz;
      for (size_t i = r.begin(); i != r.end(); ++i) hits[i] = closest_hit(bvh, rays[order[i]]);
    });
  }

  std::string params() const override { return ""; }

 private:
  BvhView bvh_;
};

}  // namespace

const ParamTable& cpu_params() {
  static const ParamTable table;
  return table;
}

std::unique_ptr<Tracer> make_cpu_tracer(ParamSet& params, const Scene&, const Bvh& bvh) {
  params.finish();
  return std::make_unique<CpuTracer>(bvh);
}

}  // namespace raycoh
