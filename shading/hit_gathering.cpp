// Hit gathering of the path tracer (path_stages.h): a wave of BSDF-sampled rays is traced as one batch, the light
// each ray finds is added to its pixel, and the hits become the next bounce's vertices.
//
// A ray that hits an emitter's front face, or misses into the sun's cone, adds that light weighted by multiple
// importance sampling with the power heuristic (beta = 2) against the next-event pdf of the same light (Veach,
// "Robust Monte Carlo Methods for Light Transport Simulation", PhD thesis 1997, ch. 9); after a delta lobe the
// weight is 1. A ray that misses always adds the sky (weight 1: the sky's only strategy). Both strategies cover
// exactly the same path lengths (up to max_depth scattering events), so the estimator is unbiased for NoOpt.
#include <numeric>

#include "shading/environment.h"
#include "shading/path_stages.h"

namespace raycoh::path_tracing {

void FrameContext::trace(const std::vector<Ray>& rays, uint64_t& counter) {
  hits.resize(rays.size());
  if (rays.empty()) return;
  const auto t0 = Clock::now();
  tracer.trace(rays.data(), rays.size(), hits.data());
  stats.trace_s += seconds_since(t0);
  counter += rays.size();
}

GBuffer shade_hits(const Scene& scene, PixelRays& rays, const std::vector<Hit>& hits, uint32_t frame) {
  const size_t n = rays.rays.size();
  rays.width = static_cast<int>(n);
  rays.height = 1;
  rays.frame = frame;
  rays.pixel.resize(n);
  std::iota(rays.pixel.begin(), rays.pixel.end(), 0u);
  return make_gbuffer(scene, rays, hits);
}

void gather_hits(FrameContext& ctx, Wave& wave, int bounce, Vertices& verts) {
  const size_t nr = wave.rays.rays.size();
  ctx.trace(wave.rays.rays, bounce == 0 ? ctx.stats.secondary_rays : ctx.stats.bounce_rays);
  const std::vector<Hit>& hits = ctx.hits;
  const GBuffer next = shade_hits(ctx.scene, wave.rays, hits, ctx.frame);
  const bool last = bounce + 1 >= ctx.settings.max_depth;
  std::vector<uint8_t> keep(nr, 0);
  const LightsView lights = ctx.emitters.view(ctx.scene);
  parallel_for_index(nr, [&](size_t i) {
    const Vec3 beta = wave.beta[i];
    if (!(max_component(beta) > 0.f)) return;
    Vec3 light(0.f);
    if (!hits[i].valid()) {
      light = missed_light(ctx.scene.env, wave.rays.rays[i].dir, wave.mis[i]);
    } else {
      const ShadingPoint& sp = next.points[i];
      light = emitted_light(lights, sp, next.materials->emission[sp.material], wave.mis[i], hits[i].t);
      keep[i] = !last;
    }
    ctx.radiance[wave.pixel[i]] += beta * light;  // one ray per pixel in a wave
  });
  verts.materials = next.materials;
  verts.sp.resize(nr);
  verts.pixel = wave.pixel;
  verts.beta = wave.beta;
  verts.mis.resize(nr);
  parallel_for_index(nr, [&](size_t i) {
    verts.sp[i] = next.points[i];
    verts.mis[i] = wave.mis[i];
    verts.mis[i].dist += hits[i].t;
  });
  compact(keep, verts.sp, verts.pixel, verts.beta, verts.mis);
}

}  // namespace raycoh::path_tracing
