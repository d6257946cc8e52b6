// Bounce sampling of the path tracer (path_stages.h): the directions leaving each bounce's vertices.
//
// The direction leaving the FIRST hit comes from the chosen generator (NoOpt, ours, ...), with the pdf and weight
// (f cos / pdf) the generator reports; with a reusing generator (ours), the first bounce's MIS weight so uses each
// pixel's own marginal pdf for diffuse groups (unbiased there), while with ours:hybrid=paper (the default) the
// hybrid groups' shared direction is not drawn from that pdf (the paper's bias; docs/hybrid-reuse.md). The other
// hybrid rules are unbiased: hybrid=glossy's weight is f cos / (the glossy pdf that drew the direction) while its
// pdf column (used here for MIS) is the member's own BSDF pdf, the one next-event estimation evaluates, so the two
// strategies' MIS weights still sum to one. Later directions are sampled
// independently with core/bsdf.h sample_direction. Russian roulette from rr_depth on: a path survives with
// probability min(1, max component of its throughput) and is divided by it (unbiased). A straight pass through a
// thin pane keeps the MIS state of the scattering event before it, as next-event estimation sees through panes.
#include <algorithm>

#include "shading/path_stages.h"

namespace raycoh::path_tracing {

void generator_directions(FrameContext& ctx, Generator& generator, const GBuffer& gbuffer, Wave& wave) {
  const Scene& scene = ctx.scene;
  RayBatch batch;
  const auto t_gen = Clock::now();
  generator.generate(scene, gbuffer, ctx.settings.seed, batch, ctx.stats.generation);
  ctx.stats.gen_s = seconds_since(t_gen);
  ctx.stats.hybrid_diffuse = hybrid_diffuse_rays(batch);
  wave.resize(batch.size());
  wave.rays.rays = batch.rays;
  parallel_for_index(batch.size(), [&](size_t i) {
    wave.pixel[i] = batch.pixel[i];
    wave.beta[i] = batch.weight[i];
    // A camera ray arrived here, so a pass through a pane keeps the camera's state (delta: weight 1).
    const ShadingPoint& sp = gbuffer.points[batch.pixel[i]];
    wave.mis[i] =
        first_bounce_mis(sp, gbuffer.materials->bsdf[sp.material], batch.rays[i].dir, batch.pdf[i], batch.material[i]);
  });
}

void sample_directions(FrameContext& ctx, const Vertices& verts, int bounce, Wave& wave) {
  const size_t nv = verts.size();
  wave.resize(nv);
  std::vector<uint8_t> keep(nv, 0);
  const bool roulette = bounce >= ctx.settings.rr_depth;
  parallel_for_index(nv, [&](size_t i) {
    const BounceSample s = sample_bounce(verts.sp[i], verts.bsdf(i), verts.beta[i], verts.mis[i], ctx.settings.seed,
                                         ctx.frame, verts.pixel[i], bounce, roulette);
    if (!s.found) return;
    wave.rays.rays[i] = s.ray;
    wave.pixel[i] = verts.pixel[i];
    wave.beta[i] = s.beta;
    wave.mis[i] = s.mis;
    keep[i] = 1;
  });
  compact(keep, wave.rays.rays, wave.pixel, wave.beta, wave.mis);
}

}  // namespace raycoh::path_tracing
