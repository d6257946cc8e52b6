// The stages of one path-traced frame and the state they hand each other (internal to shading/; the method is in
// path_tracer.cpp's doc block). Each stage is one batch step of the wavefront:
//   camera_pass            camera rays, their hits, the first path vertices           camera_pass.cpp
//   next_event_estimation  shadow rays towards emitters and the sun from a bounce      next_event.cpp
//   generator_directions   the generator's secondary batch leaving the first hits      bounce_sampling.cpp
//   sample_directions      BSDF-sampled directions of later bounces, Russian roulette  bounce_sampling.cpp
//   gather_hits            trace a wave, add the light it finds, next vertices         hit_gathering.cpp
// Every array is filled per ray or per pixel and compacted in a fixed order, so a frame is the same bits for any
// thread count.
#pragma once

#include <tbb/parallel_for.h>

#include <chrono>
#include <cstdint>
#include <vector>

#include "core/bsdf.h"
#include "core/path_vertex.h"
#include "core/rng.h"
#include "generators/generator.h"
#include "generators/primary.h"
#include "shading/emitters.h"
#include "shading/path_tracer.h"

namespace raycoh::path_tracing {

using Clock = std::chrono::steady_clock;
inline double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Per-vertex decisions (random-number dimensions, MIS state and weights, next-event and bounce samples, the light a
// ray finds) are the host/device functions of core/path_vertex.h, shared with the device path tracer.

// Rays of one batch with what shading needs next to each.
struct Wave {
  PixelRays rays;  // rays + the slot each belongs to (make_gbuffer reads this type)
  std::vector<uint32_t> pixel;
  std::vector<Vec3> beta;  // path throughput including this ray's f cos / pdf
  std::vector<MisState> mis;
  void resize(size_t n) {
    rays.rays.resize(n);
    rays.pixel.resize(n);
    pixel.resize(n);
    beta.resize(n);
    mis.resize(n);
  }
};

// Path vertices of one bounce. Their points index the material table of the G-buffer they came from.
struct Vertices {
  std::shared_ptr<const HitMaterials> materials;
  std::vector<ShadingPoint> sp;
  std::vector<uint32_t> pixel;
  std::vector<Vec3> beta;
  std::vector<MisState> mis;  // of the ray that arrived here
  size_t size() const { return sp.size(); }
  const BsdfParams& bsdf(size_t i) const { return materials->bsdf[sp[i].material]; }
};

// One frame's inputs, its per-pixel sample and its cost.
struct FrameContext {
  const Scene& scene;
  const EmitterDistribution& emitters;
  Tracer& tracer;
  const RenderSettings& settings;
  uint32_t frame;
  std::vector<Vec3> radiance;  // per pixel: this frame's sample
  std::vector<Hit> hits;       // of the last traced batch
  FrameStats stats;

  FrameContext(const Scene& s, const EmitterDistribution& e, Tracer& t, const RenderSettings& rs, uint32_t f)
      : scene(s),
        emitters(e),
        tracer(t),
        settings(rs),
        frame(f),
        radiance(static_cast<size_t>(rs.width) * static_cast<size_t>(rs.height), Vec3(0.f)) {}
  // Closest hits of rays into hits; the call is timed into stats.trace_s and the rays counted into counter.
  void trace(const std::vector<Ray>& rays, uint64_t& counter);
  // The uniform number k of pixel p's vertex of bounce b.
  float rand(uint32_t p, int bounce, BounceDim k) const { return bounce_rand(settings.seed, frame, p, bounce, k); }
  // Radiance a shading point of a G-buffer with material table t emits towards wo: emitters emit from the front
  // side of their winding only.
  static Vec3 emission(const HitMaterials& t, const ShadingPoint& sp) {
    return emission_seen(sp, t.emission[sp.material]);
  }
};

// body(i) for i in [0, n), in parallel; bodies write only their own entries.
template <typename Body>
void parallel_for_index(size_t n, Body&& body) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) body(i);
  });
}

// Keeps the entries with keep[i] != 0 of every array, in order.
template <typename... Arrays>
size_t compact(const std::vector<uint8_t>& keep, Arrays&... arrays) {
  size_t n = 0;
  for (size_t i = 0; i < keep.size(); ++i) {
    if (!keep[i]) continue;
    if (n != i) ((arrays[n] = arrays[i]), ...);
    ++n;
  }
  (arrays.resize(n), ...);
  return n;
}

// Shading points of a batch's hits in batch order: make_gbuffer on a one-row "image" whose pixel i is ray i.
GBuffer shade_hits(const Scene& scene, PixelRays& rays, const std::vector<Hit>& hits, uint32_t frame);

// The stages (see the table above). camera_pass returns the G-buffer the generator reads.
GBuffer camera_pass(FrameContext& ctx, const std::vector<uint32_t>& order, Vertices& verts);
void next_event_estimation(FrameContext& ctx, const Vertices& verts, int bounce);
void generator_directions(FrameContext& ctx, Generator& generator, const GBuffer& gbuffer, Wave& wave);
void sample_directions(FrameContext& ctx, const Vertices& verts, int bounce, Wave& wave);
void gather_hits(FrameContext& ctx, Wave& wave, int bounce, Vertices& verts);

}  // namespace raycoh::path_tracing
