// Tracer `cpu`: our own traversal (core/traverse.h, closest_hit with NoCounters) on the shared flat BVH2, or with
// `bvh=cwbvh` the compressed 8-wide BVH (core/traverse_cwbvh.h, built in the constructor from the scene by
// bvh/cwbvh_build.h, not timed), run over the batch with oneTBB, one task per block of consecutive rays.
//
// Parameters: cpu_params() below (`bvh`: bvh2 | cwbvh, default bvh2).
//
// Scenes with alpha MASK cut-outs (Scene::alpha) are traced with the AlphaTest filter of core/alpha_mask.h, which
// skips hits on transparent texels; every other scene with NoAlphaTest, the same code as without the feature.
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
#include "scenes/scene.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

// Rays per task: large enough to amortise scheduling, small enough to balance incoherent batches on few cores.
constexpr size_t kRaysPerBlock = 256;

template <class Filter>
class CpuTracer final : public Tracer {
 public:
  CpuTracer(const Bvh& bvh, Filter filter) : bvh_(bvh.view()), filter_(filter) {}

  void trace(const Ray* rays, size_t count, Hit* hits) override {
    const BvhView bvh = bvh_;
    const Filter filter = filter_;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kRaysPerBlock), [&](const tbb::blocked_range<size_t>& r) {
      const FlushDenormalsScope ftz;  // same floating-point mode as the Embree tracer, for a fair comparison
      NoCounters none;
      for (size_t i = r.begin(); i != r.end(); ++i) hits[i] = closest_hit(bvh, rays[i], none, filter);
    });
  }

  void trace_indirect(const Ray* rays, const uint32_t* order, size_t count, Hit* hits) override {
    const BvhView bvh = bvh_;
    const Filter filter = filter_;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kRaysPerBlock), [&](const tbb::blocked_range<size_t>& r) {
      const FlushDenormalsScope ftz;
      NoCounters none;
      for (size_t i = r.begin(); i != r.end(); ++i) hits[i] = closest_hit(bvh, rays[order[i]], none, filter);
    });
  }

  std::string params() const override { return "bvh=bvh2"; }

 private:
  BvhView bvh_;
  Filter filter_;
};

template <class Filter>
class CpuCwbvhTracer final : public Tracer {
 public:
  CpuCwbvhTracer(Cwbvh cwbvh, Filter filter) : cwbvh_(std::move(cwbvh)), filter_(filter) {}

  void trace(const Ray* rays, size_t count, Hit* hits) override {
    const CwbvhView bvh = cwbvh_.view();
    const Filter filter = filter_;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kRaysPerBlock), [&](const tbb::blocked_range<size_t>& r) {
      const FlushDenormalsScope ftz;
      NoCounters none;
      for (size_t i = r.begin(); i != r.end(); ++i) hits[i] = closest_hit_cwbvh(bvh, rays[i], none, filter);
    });
  }

  void trace_indirect(const Ray* rays, const uint32_t* order, size_t count, Hit* hits) override {
    const CwbvhView bvh = cwbvh_.view();
    const Filter filter = filter_;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kRaysPerBlock), [&](const tbb::blocked_range<size_t>& r) {
      const FlushDenormalsScope ftz;
      NoCounters none;
      for (size_t i = r.begin(); i != r.end(); ++i) hits[i] = closest_hit_cwbvh(bvh, rays[order[i]], none, filter);
    });
  }

  std::string params() const override { return "bvh=cwbvh"; }
  std::string bvh_layout() const override { return "cwbvh"; }

 private:
  Cwbvh cwbvh_;
  Filter filter_;
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
  if (!scene.alpha.empty()) {
    const AlphaTest alpha{scene.alpha.view()};
    if (layout == "cwbvh") return std::make_unique<CpuCwbvhTracer<AlphaTest>>(build_cwbvh(scene, bvh.config), alpha);
    return std::make_unique<CpuTracer<AlphaTest>>(bvh, alpha);
  }
  if (layout == "cwbvh")
    return std::make_unique<CpuCwbvhTracer<NoAlphaTest>>(build_cwbvh(scene, bvh.config), NoAlphaTest{});
  return std::make_unique<CpuTracer<NoAlphaTest>>(bvh, NoAlphaTest{});
}

}  // namespace raycoh
