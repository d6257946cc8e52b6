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
#include "core/rng.h"
#include "generators/generator.h"
#include "generators/primary.h"
#include "shading/emitters.h"
#include "shading/path_tracer.h"

namespace raycoh::path_tracing {

using Clock = std::chrono::steady_clock;
inline double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Random numbers of the vertex of bounce b: dimension kDimFirstFree + 16 b + k (the generator uses its own
// dimensions, core/rng.h, for the first bounce).
constexpr uint32_t kDimsPerBounce = 16;
enum BounceDim : uint32_t {
  kEmitterPick = 0,
  kEmitterU = 1,
  kEmitterV = 2,
  kSunU = 3,
  kSunV = 4,
  kDirU = 5,
  kDirV = 6,
  kLobe = 7,
  kRoulette = 8,
  kLightPick = 9
};

// Power heuristic (beta = 2) weight of the strategy with pdf a against b, written so that it never divides
// infinities: 1 / (1 + (b/a)^2).
inline float power_heuristic(float a, float b) {
  if (!(a > 0.f)) return 0.f;
  const float r = b / a;
  return 1.f / (1.f + r * r);
}

// Transmissive surfaces are a smooth dielectric: delta lobes only, so no NEE there and MIS weight 1 after them.
inline bool is_delta(MaterialClass c) { return c == MaterialClass::Transmissive; }
inline bool is_thin_pane(const BsdfParams& m) { return m.cls == MaterialClass::Transmissive && m.thin_walled; }

// How the light a ray finds is weighted (MIS state): the pdf and delta flag of the direction chosen at the
// last scattering event that was not a straight pass through a thin pane, and the distance travelled since that
// event before this ray's origin (the light pdf of an emitter is measured from there).
struct MisState {
  float pdf = 0.f;
  uint8_t delta = 1;  // a camera ray: nothing else could have found the light
  float dist = 0.f;
};

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
  float rand(uint32_t p, int bounce, BounceDim k) const {
    return rng_float(settings.seed, frame, p, kDimFirstFree + kDimsPerBounce * static_cast<uint32_t>(bounce) + k);
  }
  // Radiance a shading point of a G-buffer with material table t emits towards wo: emitters emit from the front
  // side of their winding only.
  static Vec3 emission(const HitMaterials& t, const ShadingPoint& sp) {
    return sp.cls == MaterialClass::Emissive && sp.front_face ? t.emission[sp.material] : Vec3(0.f);
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
