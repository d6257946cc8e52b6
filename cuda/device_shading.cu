// The device path tracer's stages (cuda/device_shading.h): one kernel per stage step, each calling the host/device
// function the CPU stage calls (core/path_vertex.h and below) for its vertex or ray, and a stable compaction (CUB
// exclusive sum over keep flags, then a scatter) between steps.
#include <cuda_runtime.h>

#include <cub/device/device_scan.cuh>

#include "core/error.h"
#include "core/hit_surface.h"
#include "core/path_vertex.h"
#include "cuda/cuda_check.cuh"
#include "cuda/device_common.cuh"
#include "cuda/device_shading.h"

namespace raycoh::cuda {

namespace {

constexpr int kBlock = 256;

// A path vertex: the shading point with its BSDF (a texel's on textured surfaces), pixel, throughput and the MIS
// state of the ray that arrived.
struct Vertex {
  ShadingPoint sp;
  BsdfParams bsdf;
  uint32_t pixel;
  Vec3 beta;
  MisState mis;
};

// What shading needs next to a wave's ray.
struct WaveInfo {
  uint32_t pixel;
  Vec3 beta;  // path throughput including this ray's f cos / pdf
  MisState mis;
};

// A shadow ray's slot (2i, 2i + 1 for vertex i): active while it is to be traced, arrived in the round it left the
// scene unoccluded (its light is then added by the vertex's thread).
struct ShadowSlot {
  Ray ray;
  Vec3 beta;
  uint32_t pixel;
  uint8_t panes_left, arrived;
};

__device__ BsdfParams bsdf_of(const ShadingSceneView& s, const HitSurface& h) {
  return h.textured ? h.bsdf : s.bsdf[h.point.material];
}

__global__ void camera_kernel(ShadingSceneView s, const ShadingPoint* points, const BsdfParams* table_bsdf,
                              const Vec3* table_emission, const Ray* rays, const uint32_t* pixels, const Hit* hits,
                              size_t n, Vec3* radiance, Vertex* verts, uint32_t* keep) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  const uint32_t p = pixels[i];
  keep[i] = 0;
  if (!hits[i].valid()) {
    radiance[p] = environment_radiance(s.env, rays[i].dir);
    return;
  }
  const ShadingPoint sp = load_point(points, p);
  radiance[p] = emission_seen(sp, table_emission[sp.material]);
  verts[i] = Vertex{sp, table_bsdf[sp.material], p, Vec3(1.f), MisState{}};
  keep[i] = 1;
}

__global__ void next_event_kernel(ShadingSceneView s, const Vertex* verts, size_t nv, uint32_t seed, uint32_t frame,
                                  int bounce, uint8_t panes, ShadowSlot* slots, uint32_t* active) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (i >= nv) return;
  const Vertex& v = verts[i];
  ShadowSample out[2];
  next_event_rays(s.lights, s.env, s.sun, v.sp, v.bsdf, v.beta, seed, frame, v.pixel, bounce, out);
  for (int k = 0; k < 2; ++k) {
    slots[2 * i + k] = ShadowSlot{out[k].ray, out[k].beta, v.pixel, panes, 0};
    active[2 * i + k] = out[k].found ? 1u : 0u;
  }
}

__global__ void shadow_rays_kernel(const ShadowSlot* slots, const uint32_t* index, size_t m, Ray* rays) {
  const size_t j = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (j < m) rays[j] = slots[index[j]].ray;
}

// A traced shadow ray: arrived when it missed; through a thin pane it stays active (core/path_vertex.h pass_pane).
__global__ void shadow_resolve_kernel(ShadingSceneView s, const uint32_t* index, const Ray* rays, const Hit* hits,
                                      size_t m, ShadowSlot* slots, uint32_t* active) {
  const size_t j = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (j >= m) return;
  const uint32_t k = index[j];
  ShadowSlot& slot = slots[k];
  const Hit h = hits[j];
  if (!h.valid()) {
    slot.arrived = 1;
    active[k] = 0;
    return;
  }
  const HitSurface surface = hit_surface(s.mesh, rays[j], h);
  active[k] = pass_pane(surface.point, bsdf_of(s, surface), h.t, slot.ray, slot.beta, slot.panes_left) ? 1u : 0u;
}

// The light of vertex i's arrived shadow rays, slot 2i before 2i + 1 (the CPU's batch order).
__global__ void shadow_add_kernel(ShadowSlot* slots, size_t nv, Vec3* radiance) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (i >= nv) return;
  for (int k = 0; k < 2; ++k) {
    ShadowSlot& slot = slots[2 * i + k];
    if (!slot.arrived) continue;
    radiance[slot.pixel] += slot.beta;
    slot.arrived = 0;
  }
}

__global__ void first_bounce_kernel(BatchView batch, size_t n, const ShadingPoint* points, const BsdfParams* table_bsdf,
                                    Ray* rays, WaveInfo* info) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  const Ray r = batch.rays[i];
  const uint32_t p = batch.pixel[i];
  const ShadingPoint sp = load_point(points, p);
  rays[i] = r;
  info[i] = WaveInfo{p, batch.weight[i],
                     first_bounce_mis(sp, table_bsdf[sp.material], r.dir, batch.pdf[i], batch.material[i])};
}

__global__ void sample_kernel(const Vertex* verts, size_t nv, uint32_t seed, uint32_t frame, int bounce, bool roulette,
                              Ray* rays, WaveInfo* info, uint32_t* keep) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (i >= nv) return;
  const Vertex& v = verts[i];
  const BounceSample s = sample_bounce(v.sp, v.bsdf, v.beta, v.mis, seed, frame, v.pixel, bounce, roulette);
  keep[i] = s.found ? 1u : 0u;
  if (!s.found) return;
  rays[i] = s.ray;
  info[i] = WaveInfo{v.pixel, s.beta, s.mis};
}

__global__ void gather_kernel(ShadingSceneView s, const Ray* rays, const WaveInfo* info, const Hit* hits, size_t n,
                              bool last, Vec3* radiance, Vertex* verts, uint32_t* keep) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  keep[i] = 0;
  const WaveInfo w = info[i];
  if (!(max_component(w.beta) > 0.f)) return;
  const Hit h = hits[i];
  Vec3 light(0.f);
  if (!h.valid()) {
    light = missed_light(s.env, rays[i].dir, w.mis);
  } else {
    const HitSurface surface = hit_surface(s.mesh, rays[i], h);
    const Vec3 le = surface.textured ? surface.emission : s.emission[surface.point.material];
    light = emitted_light(s.lights, surface.point, le, w.mis, h.t);
    MisState mis = w.mis;
    mis.dist += h.t;
    verts[i] = Vertex{surface.point, bsdf_of(s, surface), w.pixel, w.beta, mis};
    keep[i] = last ? 0u : 1u;
  }
  radiance[w.pixel] += w.beta * light;  // one ray per pixel in a wave
}

__global__ void scatter_index_kernel(const uint32_t* keep, const uint32_t* scan, size_t n, uint32_t* index) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (i < n && keep[i]) index[scan[i]] = static_cast<uint32_t>(i);
}

template <class T>
__global__ void gather_by_index_kernel(const T* src, const uint32_t* index, size_t m, T* dst) {
  const size_t j = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (j < m) dst[j] = src[index[j]];
}

template <class T>
void gather_by_index(const DeviceBuffer<T>& src, const DeviceBuffer<uint32_t>& index, size_t m, DeviceBuffer<T>& dst) {
  dst.reserve(m);
  if (m == 0) return;
  gather_by_index_kernel<<<blocks_for(m, kBlock), kBlock>>>(src.get(), index.get(), m, dst.get());
  RAYCOH_CUDA_CHECK_LAUNCH();
}

}  // namespace

struct DeviceShading::Impl {
  const DeviceSceneShading& scene;
  DeviceTracer& tracer;
  TraceLaunch launch;
  DevicePathSettings settings;
  uint32_t frame = 0;
  size_t nv = 0, nw = 0;     // vertices, rays of the current wave
  bool wave_traced = false;  // the current wave's hits are already in `hits` (a fused first bounce)
  DeviceRayCounts counts;
  DeviceBuffer<Vec3> radiance;
  DeviceGBufferView gbuffer;  // the camera pass's, on the device (points, table_bsdf, table_emission)
  StageClock* clock = nullptr;
  TraceStages trace_stages;
  DeviceBuffer<Vertex> verts, sparse_verts;
  DeviceBuffer<ShadowSlot> slots;
  DeviceBuffer<Ray> rays, sparse_rays, shadow_rays;
  DeviceBuffer<WaveInfo> info, sparse_info;
  DeviceBuffer<Hit> hits;
  DeviceBuffer<uint32_t> keep, scan, index;
  DeviceBuffer<uint8_t> scan_temp;

  Impl(const DeviceSceneShading& s, DeviceTracer& t, const TraceLaunch& l, const DevicePathSettings& ps)
      : scene(s), tracer(t), launch(l), settings(ps) {
    const size_t pixels = static_cast<size_t>(ps.width) * static_cast<size_t>(ps.height);
    radiance.reserve(pixels);
    verts.reserve(pixels);
    sparse_verts.reserve(pixels);
    slots.reserve(2 * pixels);
    keep.reserve(2 * pixels);
    scan.reserve(2 * pixels);
    index.reserve(2 * pixels);
  }

  // index[0, m) = the positions of the non-zero keep[0, n), in order (CUB exclusive sum, then a scatter); returns m.
  size_t compact(size_t n) {
    if (n == 0) return 0;
    size_t bytes = 0;
    const int count = static_cast<int>(n);
    RAYCOH_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(nullptr, bytes, keep.get(), scan.get(), count));
    scan_temp.reserve(bytes);
    RAYCOH_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(scan_temp.get(), bytes, keep.get(), scan.get(), count));
    scatter_index_kernel<<<blocks_for(n, kBlock), kBlock>>>(keep.get(), scan.get(), n, index.get());
    RAYCOH_CUDA_CHECK_LAUNCH();
    uint32_t last[2] = {0, 0};
    RAYCOH_CUDA_CHECK(cudaMemcpy(&last[0], scan.get() + n - 1, sizeof(uint32_t), cudaMemcpyDeviceToHost));
    RAYCOH_CUDA_CHECK(cudaMemcpy(&last[1], keep.get() + n - 1, sizeof(uint32_t), cudaMemcpyDeviceToHost));
    return static_cast<size_t>(last[0]) + last[1];
  }

  // Closest hits of rays[0, n) into hits (the device trace kernel), timed as clock stage `stage`.
  void trace(const Ray* d_rays, size_t n, int stage) {
    hits.reserve(n);
    if (n == 0) return;
    const int was = clock ? clock->enter(stage) : 0;
    tracer.trace_device(d_rays, nullptr, n, hits.get(), launch);
    if (clock) clock->enter(was);
  }

  // Shadow rounds: trace the active slots, resolve them, add what arrived, until none is active.
  void shadow_rounds() {
    for (;;) {
      const size_t m = compact(2 * nv);
      if (m == 0) return;
      shadow_rays.reserve(m);
      shadow_rays_kernel<<<blocks_for(m, kBlock), kBlock>>>(slots.get(), index.get(), m, shadow_rays.get());
      RAYCOH_CUDA_CHECK_LAUNCH();
      trace(shadow_rays.get(), m, trace_stages.other);
      counts.shadow += m;
      const ShadingSceneView& s = scene.view();
      shadow_resolve_kernel<<<blocks_for(m, kBlock), kBlock>>>(s, index.get(), shadow_rays.get(), hits.get(), m,
                                                               slots.get(), keep.get());
      RAYCOH_CUDA_CHECK_LAUNCH();
      shadow_add_kernel<<<blocks_for(nv, kBlock), kBlock>>>(slots.get(), nv, radiance.get());
      RAYCOH_CUDA_CHECK_LAUNCH();
    }
  }

  // The vertices kept in sparse_verts[0, n) (keep flags) become verts[0, nv).
  void compact_vertices(size_t n) {
    nv = compact(n);
    gather_by_index(sparse_verts, index, nv, verts);
  }
};

DeviceShading::DeviceShading(const DeviceSceneShading& scene, DeviceTracer& tracer, const TraceLaunch& launch,
                             const DevicePathSettings& settings)
    : impl_(std::make_unique<Impl>(scene, tracer, launch, settings)) {}

DeviceShading::~DeviceShading() = default;

void DeviceShading::set_clock(StageClock* clock, const TraceStages& stages) {
  impl_->clock = clock;
  impl_->trace_stages = stages;
}

void DeviceShading::camera(uint32_t frame, const DeviceGBufferView& gbuffer, const Ray* d_rays,
                           const uint32_t* d_pixels, const Hit* d_hits, size_t n) {
  Impl& d = *impl_;
  const size_t pixels = static_cast<size_t>(d.settings.width) * static_cast<size_t>(d.settings.height);
  RAYCOH_CHECK(n == pixels && gbuffer.pixels() == pixels && gbuffer.points && gbuffer.bsdf && gbuffer.emission,
               "device camera pass: one ray per pixel and a G-buffer with its material table");
  d.frame = frame;
  d.counts = DeviceRayCounts{};
  d.counts.primary = n;
  d.gbuffer = gbuffer;
  d.radiance.zero(pixels);
  camera_kernel<<<blocks_for(n, kBlock), kBlock>>>(d.scene.view(), gbuffer.points, gbuffer.bsdf, gbuffer.emission,
                                                   d_rays, d_pixels, d_hits, n, d.radiance.get(), d.sparse_verts.get(),
                                                   d.keep.get());
  RAYCOH_CUDA_CHECK_LAUNCH();
  d.compact_vertices(n);
}

size_t DeviceShading::vertices() const { return impl_->nv; }

void DeviceShading::next_event(int bounce) {
  Impl& d = *impl_;
  if (d.nv == 0) return;
  const int panes = d.settings.max_depth - 1 - bounce;
  next_event_kernel<<<blocks_for(d.nv, kBlock), kBlock>>>(d.scene.view(), d.verts.get(), d.nv, d.settings.seed, d.frame,
                                                          bounce, static_cast<uint8_t>(panes < 255 ? panes : 255),
                                                          d.slots.get(), d.keep.get());
  RAYCOH_CUDA_CHECK_LAUNCH();
  d.shadow_rounds();
}

Hit* DeviceShading::first_wave_hits(size_t n) {
  impl_->hits.reserve(n);
  return impl_->hits.get();
}

void DeviceShading::first_bounce(const BatchView& batch, size_t n, bool traced) {
  Impl& d = *impl_;
  d.nw = n;
  d.wave_traced = traced;
  d.rays.reserve(n);
  d.info.reserve(n);
  if (n == 0) return;
  first_bounce_kernel<<<blocks_for(n, kBlock), kBlock>>>(batch, n, d.gbuffer.points, d.gbuffer.bsdf, d.rays.get(),
                                                         d.info.get());
  RAYCOH_CUDA_CHECK_LAUNCH();
}

void DeviceShading::sample(int bounce) {
  Impl& d = *impl_;
  d.sparse_rays.reserve(d.nv);
  d.sparse_info.reserve(d.nv);
  if (d.nv > 0) {
    sample_kernel<<<blocks_for(d.nv, kBlock), kBlock>>>(d.verts.get(), d.nv, d.settings.seed, d.frame, bounce,
                                                        bounce >= d.settings.rr_depth, d.sparse_rays.get(),
                                                        d.sparse_info.get(), d.keep.get());
    RAYCOH_CUDA_CHECK_LAUNCH();
  }
  d.nw = d.compact(d.nv);
  gather_by_index(d.sparse_rays, d.index, d.nw, d.rays);
  gather_by_index(d.sparse_info, d.index, d.nw, d.info);
}

void DeviceShading::gather(int bounce) {
  Impl& d = *impl_;
  const TraceStages& t = d.trace_stages;
  if (!d.wave_traced) d.trace(d.rays.get(), d.nw, bounce == 0 ? t.first_wave : bounce == 1 ? t.second_wave : t.other);
  d.wave_traced = false;
  (bounce == 0 ? d.counts.secondary : d.counts.bounce) += d.nw;
  if (bounce == 1) d.counts.second = d.nw;
  if (d.nw > 0) {
    gather_kernel<<<blocks_for(d.nw, kBlock), kBlock>>>(d.scene.view(), d.rays.get(), d.info.get(), d.hits.get(), d.nw,
                                                        bounce + 1 >= d.settings.max_depth, d.radiance.get(),
                                                        d.sparse_verts.get(), d.keep.get());
    RAYCOH_CUDA_CHECK_LAUNCH();
  }
  d.compact_vertices(d.nw);
}

void DeviceShading::download_radiance(std::vector<Vec3>& out) const {
  const size_t pixels = static_cast<size_t>(impl_->settings.width) * static_cast<size_t>(impl_->settings.height);
  out.resize(pixels);
  impl_->radiance.download(out.data(), pixels);
}

const DeviceRayCounts& DeviceShading::counts() const { return impl_->counts; }

}  // namespace raycoh::cuda
