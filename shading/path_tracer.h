// The path tracer of the quality runs: the benchmark's own pipeline (primary rays, G-buffer, generator, tracer)
// with shading on top, traced wavefront style — one tracer call per batch (camera rays, the generator's
// secondary batch, each later bounce, each bounce's shadow rays), so the timed trace is the same tracer code the
// benchmark measures. The method is in path_tracer.cpp's doc block; its stages are in path_stages.h.
//
// RenderSettings (validated by validate(); raycoh::Error names the field):
//   width, height  int     160 x 120   [1, 16384]: image size
//   seed           uint    1           any: random numbers are rng(seed, frame, pixel, dimension)
//   max_depth      int     5           [1, 64]: scattering events per path (1 = direct light only)
//   rr_depth       int     3           [1, 64]: Russian roulette on the rays leaving the rr_depth-th scattering
//                                      event and later (counted from 0 at the first hit), so the generator's
//                                      batch is always traced whole
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "generators/generator.h"
#include "scenes/scene.h"
#include "shading/environment.h"  // sky_radiance, in_sun_cone, environment_radiance
#include "shading/image.h"
#include "tracers/tracer.h"

namespace raycoh {

struct RenderSettings {
  int width = 160, height = 120;
  uint32_t seed = 1;
  int max_depth = 5;
  int rr_depth = 3;
  void validate() const;
};

// One frame's cost and counts.
struct FrameStats {
  double wall_s = 0;   // the whole frame: rays, G-buffer, generation, tracing, shading, accumulation
  double trace_s = 0;  // sum of the wall-clock times of the tracer calls
  double gen_s = 0;    // the generator's call
  uint64_t primary_rays = 0, secondary_rays = 0, bounce_rays = 0, shadow_rays = 0;
  uint64_t non_finite = 0;  // pixels whose frame sample was NaN/Inf: counted and not accumulated
  GenerationStats generation;
  uint64_t hybrid_diffuse = 0;  // first-bounce rays of generators/generator.h hybrid_diffuse_rays (of generation.rays)
  uint64_t rays() const { return primary_rays + secondary_rays + bounce_rays + shadow_rays; }
  void add(const FrameStats& f);
};

struct EmitterDistribution;

// The first-hit features a denoiser takes as auxiliary images (shading/denoise.h), per pixel and frame: the albedo
// (the hit material's base colour clamped to [0, 1]; 1 on transmissive surfaces, which OIDN asks for dielectrics)
// and the unit shading normal in world space. A pixel whose camera ray missed gets 0 for both.
struct AuxSample {
  Vec3 albedo{0.f}, normal{0.f};
};
AuxSample aux_of(const HitMaterials& materials, const ShadingPoint& sp);
// The auxiliary images summed over frames like the colour (their mean is what the denoiser reads).
struct AuxAccumulators {
  Accumulator albedo, normal;
  AuxAccumulators() = default;
  AuxAccumulators(int width, int height) : albedo(width, height), normal(width, height) {}
};

class PathTracer {
 public:
  // scene, tracer and generator must outlive the path tracer; the tracer must have been made for this scene.
  PathTracer(const Scene& scene, Tracer& tracer, Generator& generator, const RenderSettings& settings);
  ~PathTracer();
  // Renders frame `frame` (one path per pixel) and adds it to acc, which must have the settings' size; with aux,
  // also the frame's first-hit albedo and normal (aux_of) from the G-buffer of its camera pass.
  FrameStats render_frame(uint32_t frame, Accumulator& acc, AuxAccumulators* aux = nullptr);
  // Only frame `frame`'s camera pass, its first-hit albedo and normal added to aux as render_frame adds them: the
  // denoiser's auxiliary images of a frame whose colour is rendered elsewhere (the device path tracer, whose camera
  // rays are these bit for bit; harness/image/frame_source.h).
  void first_hits(uint32_t frame, AuxAccumulators& aux);
  // Frames first .. first + count - 1.
  FrameStats render_frames(uint32_t first, int count, Accumulator& acc);
  const RenderSettings& settings() const { return settings_; }

 private:
  const Scene& scene_;
  Tracer& tracer_;
  Generator& generator_;
  RenderSettings settings_;
  std::vector<uint32_t> primary_order_;
  std::unique_ptr<EmitterDistribution> emitters_;
};

}  // namespace raycoh
