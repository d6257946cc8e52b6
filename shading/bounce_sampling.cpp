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
    const bool pass = is_thin_pane(gbuffer.materials->bsdf[sp.material]) && dot(batch.rays[i].dir, sp.ng) < 0.f;
    wave.mis[i] = pass ? MisState{} : MisState{batch.pdf[i], is_delta(batch.material[i]), 0.f};
  });
}

void sample_directions(FrameContext& ctx, const Vertices& verts, int bounce, Wave& wave) {
  const size_t nv = verts.size();
  wave.resize(nv);
  std::vector<uint8_t> keep(nv, 0);
  const bool roulette = bounce >= ctx.settings.rr_depth;
  parallel_for_index(nv, [&](size_t i) {
    const ShadingPoint& sp = verts.sp[i];
    const uint32_t p = verts.pixel[i];
    const DirectionSample s =
        sample_direction(verts.bsdf(i), sp.ns, sp.ng, sp.wo, sp.front_face, ctx.rand(p, bounce, kDirU),
                         ctx.rand(p, bounce, kDirV), ctx.rand(p, bounce, kLobe));
    Vec3 beta = verts.beta[i] * s.weight;
    if (!(max_component(beta) > 0.f)) return;
    if (roulette) {
      const float survive = std::min(1.f, max_component(beta));
      if (ctx.rand(p, bounce, kRoulette) >= survive) return;
      beta = beta * (1.f / survive);
    }
    Ray& r = wave.rays.rays[i];
    r.org = offset_ray_origin(sp.position, dot(s.dir, sp.ng) >= 0.f ? sp.ng : -sp.ng);
    r.dir = s.dir;
    r.tmin = 0.f;
    r.tmax = __builtin_huge_valf();
    wave.pixel[i] = p;
    wave.beta[i] = beta;
    const bool pass = (s.flags & kSampleTransmitted) != 0 && is_thin_pane(verts.bsdf(i));
    wave.mis[i] = pass ? verts.mis[i] : MisState{s.pdf, is_delta(sp.cls), 0.f};
    keep[i] = 1;
  });
  compact(keep, wave.rays.rays, wave.pixel, wave.beta, wave.mis);
}

}  // namespace raycoh::path_tracing
