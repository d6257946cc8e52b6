// Tracer `embree`: the same ray batches traced by Embree 3, as a wall-clock CPU baseline and as the correctness
// oracle for our traversal. Embree builds its own acceleration structure from the scene's triangles in the
// constructor (not part of the timed trace).
//
// Parameters: embree_params() below.
//   mode
//     single             rtcIntersect1 per ray (Embree ignores the coherence flag here)
//     packet16           rtcIntersect16 on 16 consecutive rays of the batch, flag COHERENT
//     stream_coherent    rtcIntersect1M on blocks of 256 consecutive rays, flag COHERENT
//     stream_incoherent  rtcIntersect1M on blocks of 256 consecutive rays, flag INCOHERENT
//   quality
//     high    RTC_BUILD_QUALITY_HIGH: SAH with spatial splits, Embree's best tree for static scenes
//     medium  RTC_BUILD_QUALITY_MEDIUM: binned SAH, the builder our own BVH uses (for like-for-like runs)
//
// Follows Wald et al., "Embree: A Kernel Framework for Efficient CPU Ray Tracing" (SIGGRAPH 2014); packets after
// Wald et al., "Interactive Rendering with Coherent Ray Tracing" (Eurographics 2001).
//
// Results use our conventions: t = tfar, prim = primID, (u, v) = Embree's (u, v), which weight v1 and v2 as ours
// do. A ray that misses, or is rejected up front, returns Hit{t = tmax, prim = kNoHit}, exactly like
// closest_hit(). Rays with tmax <= tmin, a non-finite origin or direction, or a zero direction are rejected here
// with the same rule as traversal_begin(), so Embree never sees them. Embree requires tmin >= 0; a negative tmin
// is passed on unchanged and its result is Embree's to define. Alpha MASK cut-outs (Scene::alpha) are an Embree
// intersection filter that runs the same test as our traversal (core/alpha_mask.h); scenes without them have no
// filter.
#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "bvh/bvh_build.h"
#include "core/alpha_mask.h"
#include "core/error.h"
#include "core/flush_denormals.h"
#include "embree/embree_device.h"
#include "scenes/scene.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

// Rays per task; a multiple of 16 so that packets never straddle two tasks, and the stream length handed to
// rtcIntersect1M, which Embree regroups into packets internally.
constexpr size_t kRaysPerBlock = 256;
constexpr size_t kPacket = 16;
static_assert(kRaysPerBlock % kPacket == 0, "packets must not straddle blocks");

enum class Mode { Single, Packet16, StreamCoherent, StreamIncoherent };

// The same acceptance rule as traversal_begin() in core/traverse.h.
inline bool traceable(const Ray& r) {
  return r.tmax > r.tmin && is_finite(r.org) && is_finite(r.dir) && dot(r.dir, r.dir) > 0.f;
}

inline Hit miss(const Ray& r) {
  Hit h;
  h.t = r.tmax;
  return h;
}

inline void to_embree(const Ray& r, RTCRayHit& rh) {
  rh.ray.org_x = r.org.x;
  rh.ray.org_y = r.org.y;
  rh.ray.org_z = r.org.z;
  rh.ray.tnear = r.tmin;
  rh.ray.dir_x = r.dir.x;
  rh.ray.dir_y = r.dir.y;
  rh.ray.dir_z = r.dir.z;
  rh.ray.time = 0.f;
  rh.ray.tfar = r.tmax;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

// Stands in for a rejected ray in streams and masked packet lanes: finite, so that the arithmetic Embree does on
// idle SIMD lanes stays quiet, and with tnear > tfar, which Embree skips.
constexpr Ray kIdleRay{Vec3{0.f}, 1.f, Vec3{0.f, 0.f, 1.f}, 0.f};

inline Hit from_embree(const Ray& r, const RTCRayHit& rh) {
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return miss(r);
  Hit h;
  h.t = rh.ray.tfar;
  h.prim = rh.hit.primID;
  h.u = rh.hit.u;
  h.v = rh.hit.v;
  return h;
}

// Embree's intersection filter for alpha cut-outs: rejects candidate hits on transparent texels.
void alpha_filter(const RTCFilterFunctionNArguments* args) {
  const auto* alpha = static_cast<const AlphaTest*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    if (!alpha->accept(RTCHitN_primID(args->hit, args->N, i), RTCHitN_u(args->hit, args->N, i),
                       RTCHitN_v(args->hit, args->N, i)))
      args->valid[i] = 0;
  }
}

class EmbreeTracer final : public Tracer {
 public:
  EmbreeTracer(const Scene& scene, Mode mode, bool high_quality, std::string params)
      : mode_(mode), params_(std::move(params)), alpha_{scene.alpha.view()} {
    RTCDevice device = embree_device();
    if (rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_BACKFACE_CULLING_ENABLED))
      throw Error(
          fmt::format("this Embree {} was built with back-face culling; raycoh's triangles are "
                      "double-sided, so its results would not match (rebuild Embree without "
                      "EMBREE_BACKFACE_CULLING)",
                      embree_version()));
    if (!scene.alpha.empty() && !rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_FILTER_FUNCTION_SUPPORTED))
      throw Error(
          fmt::format("scene '{}' has alpha MASK cut-outs, which need Embree's filter functions; this Embree "
                      "{} was built without them (EMBREE_FILTER_FUNCTION)",
                      scene.name, embree_version()));
    // Checked before any Embree object exists, so that a throw leaks nothing.
    for (size_t i = 0; i < scene.indices.size(); ++i)
      if (scene.indices[i] >= scene.positions.size())
        throw Error(fmt::format("scene '{}': triangle {} uses vertex {}, but there are {} vertices", scene.name, i / 3,
                                scene.indices[i], scene.positions.size()));
    const std::string what = fmt::format("building the Embree scene of '{}'", scene.name);
    scene_.reset(rtcNewScene(device));
    embree_check(what);
    const RTCBuildQuality quality = high_quality ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM;
    rtcSetSceneBuildQuality(scene_.get(), quality);

    const std::unique_ptr<RTCGeometryTy, decltype(&rtcReleaseGeometry)> geom(
        rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE), rtcReleaseGeometry);
    embree_check(what);
    rtcSetGeometryBuildQuality(geom.get(), quality);
    // Embree-allocated buffers rather than shared ones: Embree reads vertices with 16-byte loads and needs padding
    // past the last vertex, which scene.positions does not have.
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom.get(), RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), scene.positions.size()));
    auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
        geom.get(), RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), scene.triangle_count()));
    embree_check(what);
    for (size_t i = 0; i < scene.positions.size(); ++i) {
      vertices[3 * i + 0] = scene.positions[i].x;
      vertices[3 * i + 1] = scene.positions[i].y;
      vertices[3 * i + 2] = scene.positions[i].z;
    }
    std::copy(scene.indices.begin(), scene.indices.begin() + 3 * scene.triangle_count(), indices);
    if (!scene.alpha.empty()) {
      rtcSetGeometryUserData(geom.get(), &alpha_);
      rtcSetGeometryIntersectFilterFunction(geom.get(), alpha_filter);
    }
    rtcCommitGeometry(geom.get());
    // geomID 0: primID is then the scene's triangle index, as in our BVH.
    rtcAttachGeometryByID(scene_.get(), geom.get(), 0);
    rtcCommitScene(scene_.get());
    embree_check(what);
  }

  void trace(const Ray* rays, size_t count, Hit* hits) override { run(RaySource{rays, nullptr}, count, hits); }
  void trace_indirect(const Ray* rays, const uint32_t* order, size_t count, Hit* hits) override {
    run(RaySource{rays, order}, count, hits);
  }

  std::string params() const override { return params_; }
  std::string bvh_layout() const override { return "embree"; }

 private:
  // Ray i of the batch: rays[i], or rays[order[i]] when tracing through sorted indices.
  struct RaySource {
    const Ray* rays;
    const uint32_t* order;
    const Ray& operator[](size_t i) const { return order ? rays[order[i]] : rays[i]; }
  };

  void run(RaySource rays, size_t count, Hit* hits) {
    const size_t blocks = (count + kRaysPerBlock - 1) / kRaysPerBlock;
    // simple_partitioner: exactly one block per task, so streams are kRaysPerBlock long and packets aligned.
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, blocks, 1),
        [&](const tbb::blocked_range<size_t>& r) {
          const FlushDenormalsScope ftz;
          for (size_t b = r.begin(); b != r.end(); ++b) {
            const size_t begin = b * kRaysPerBlock, end = std::min(count, begin + kRaysPerBlock);
            switch (mode_) {
              case Mode::Single:
                trace_single(rays, hits, begin, end);
                break;
              case Mode::Packet16:
                trace_packets(rays, hits, begin, end);
                break;
              case Mode::StreamCoherent:
                trace_stream(rays, hits, begin, end, RTC_INTERSECT_CONTEXT_FLAG_COHERENT);
                break;
              case Mode::StreamIncoherent:
                trace_stream(rays, hits, begin, end, RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT);
                break;
            }
          }
          embree_check("tracing rays with Embree");
        },
        tbb::simple_partitioner());
  }

  void trace_single(RaySource rays, Hit* hits, size_t begin, size_t end) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (size_t i = begin; i < end; ++i) {
      if (!traceable(rays[i])) {
        hits[i] = miss(rays[i]);
        continue;
      }
      RTCRayHit rh;
      to_embree(rays[i], rh);
      rtcIntersect1(scene_.get(), &ctx, &rh);
      hits[i] = from_embree(rays[i], rh);
    }
  }

  void trace_packets(RaySource rays, Hit* hits, size_t begin, size_t end) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    for (size_t base = begin; base < end; base += kPacket) {
      const size_t n = std::min(kPacket, end - base);
      alignas(64) int valid[kPacket];
      RTCRayHit16 p;
      for (size_t k = 0; k < kPacket; ++k) {
        const bool live = k < n && traceable(rays[base + k]);
        valid[k] = live ? -1 : 0;
        const Ray& r = live ? rays[base + k] : kIdleRay;
        p.ray.org_x[k] = r.org.x;
        p.ray.org_y[k] = r.org.y;
        p.ray.org_z[k] = r.org.z;
        p.ray.tnear[k] = r.tmin;
        p.ray.dir_x[k] = r.dir.x;
        p.ray.dir_y[k] = r.dir.y;
        p.ray.dir_z[k] = r.dir.z;
        p.ray.time[k] = 0.f;
        p.ray.tfar[k] = r.tmax;
        p.ray.mask[k] = 0xFFFFFFFFu;
        p.ray.id[k] = static_cast<unsigned>(k);
        p.ray.flags[k] = 0;
        p.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        p.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect16(valid, scene_.get(), &ctx, &p);
      for (size_t k = 0; k < n; ++k) {
        const Ray& r = rays[base + k];
        Hit h = miss(r);
        if (valid[k] && p.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID) {
          h.t = p.ray.tfar[k];
          h.prim = p.hit.primID[k];
          h.u = p.hit.u[k];
          h.v = p.hit.v[k];
        }
        hits[base + k] = h;
      }
    }
  }

  void trace_stream(RaySource rays, Hit* hits, size_t begin, size_t end, RTCIntersectContextFlags flag) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = flag;
    RTCRayHit stream[kRaysPerBlock];
    const size_t n = end - begin;
    for (size_t k = 0; k < n; ++k) {
      if (traceable(rays[begin + k]))
        to_embree(rays[begin + k], stream[k]);
      else
        to_embree(kIdleRay, stream[k]);
    }
    rtcIntersect1M(scene_.get(), &ctx, stream, static_cast<unsigned>(n), sizeof(RTCRayHit));
    for (size_t k = 0; k < n; ++k) hits[begin + k] = from_embree(rays[begin + k], stream[k]);
  }

  std::unique_ptr<RTCSceneTy, decltype(&rtcReleaseScene)> scene_{nullptr, rtcReleaseScene};
  Mode mode_;
  std::string params_;
  AlphaTest alpha_;  // read by alpha_filter through the geometry's user pointer
};

}  // namespace

const ParamTable& embree_params() {
  static const ParamTable table = {
      choice_param("mode", "single", {"single", "packet16", "stream_coherent", "stream_incoherent"},
                   "Embree call per ray, per 16 rays, or per stream of 256 (see embree_tracer.cpp)"),
      choice_param("quality", "high", {"high", "medium"}, "Embree's build: SAH with spatial splits, or binned SAH"),
  };
  return table;
}

std::unique_ptr<Tracer> make_embree_tracer(ParamSet& params, const Scene& scene, const Bvh&) {
  const std::string mode = params.get_choice("mode");
  const std::string quality = params.get_choice("quality");
  params.finish();
  const Mode m = mode == "packet16"            ? Mode::Packet16
                 : mode == "stream_coherent"   ? Mode::StreamCoherent
                 : mode == "stream_incoherent" ? Mode::StreamIncoherent
                                               : Mode::Single;
  return std::make_unique<EmbreeTracer>(scene, m, quality == "high", params.canonical());
}

}  // namespace raycoh
