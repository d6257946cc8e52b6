// Tracer `cpu`: our own traversal (core/traverse.h, closest_hit with NoCounters) on the shared flat BVH2, or with
// `bvh=cwbvh` the compressed 8-wide BVH (core/traverse_cwbvh.h, built in the constructor from the scene by
// bvh/cwbvh_build.h, not timed), run over the batch with oneTBB, one task per block of consecutive rays.
//
// Parameters: cpu_params() below (`bvh`: bvh2 | cwbvh, default bvh2).
//
// Follows Aila & Laine, "Understanding the Efficiency of Ray Traversal on GPUs" (HPG 2009): while-while traversal
// of a two-boxes-per-node BVH2, with the watertight triangle test of Woop, Benthin and Wald (JCGT 2013). Every
// ray is independent, so the hits are the same whatever the thread count or scheduling.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <memory>

#include "bvh/bvh_build.h"
#include "bvh/cwbvh_build.h"
#include "core/flush_denormals.h"
#include "core/traverse.h"
#include "core/traverse_cwbvh.h"
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

  std::string params() const override { return "bvh=bvh2"; }

 private:
  BvhView bvh_;
};

class CpuCwbvhTracer final : public Tracer {
 public:
  explicit CpuCwbvhTracer(Cwbvh cwbvh) : cwbvh_(std::move(cwbvh)) {}

  void trace(const Ray* rays, size_t count, Hit* hits) override {
    const CwbvhView bvh = cwbvh_.view();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kRaysPerBlock), [&](const tbb::blocked_range<size_t>& r) {
      const FlushDenormalsScope ftz;
      for (size_t i = r.begin(); i != r.end(); ++i) hits[i] = closest_hit_cwbvh(bvh, rays[i]);
    });
  }

  void trace_indirect(const Ray* rays, const uint32_t* order, size_t count, Hit* hits) override {
    const CwbvhView bvh = cwbvh_.view();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kRaysPerBlock), [&](const tbb::blocked_range<size_t>& r) {
      const FlushDenormalsScope ftz;
      for (size_t i = r.begin(); i != r.end(); ++i) hits[i] = closest_hit_cwbvh(bvh, rays[order[i]]);
    });
  }

  std::string params() const override { return "bvh=cwbvh"; }

 private:
  Cwbvh cwbvh_;
};

}  // namespace

const ParamTable& cpu_params() {
  static const ParamTable table = {
      choice_param("bvh", "bvh2", {"bvh2", "cwbvh"},
                   "layout: the shared BVH2, or the compressed 8-wide BVH (Ylitie et al. 2017) built from the scene"),
  };
  return table;
}

std::unique_ptr<Tracer> make_cpu_tracer(ParamSet& params, const Scene& scene, const Bvh& bvh) {
  const std::string layout = params.get_choice("bvh");
  params.finish();
  if (layout == "cwbvh") return std::make_unique<CpuCwbvhTracer>(build_cwbvh(scene, bvh.config));
  return std::make_unique<CpuTracer>(bvh);
}

}  // namespace raycoh
