// Next-event estimation of the path tracer (path_stages.h), at every path vertex with a non-delta BSDF (diffuse,
// emissive, glossy, specular: core/bsdf.h): one shadow ray per light kind, an emitter (shading/emitters.h) in slot
// 2i and, in slot 2i + 1, the sun's cone (shading/environment.h) or a punctual light (emitters.h): a scene has
// one or the other, since finalize_scene switches the environment off in scenes with punctual lights. Emitter
// and sun are weighted by multiple importance sampling with the power heuristic against BSDF sampling of the
// same direction (Veach, "Robust Monte Carlo Methods for Light Transport Simulation", PhD thesis 1997, ch. 9);
// punctual lights are delta lights that BSDF sampling never finds, so their weight is 1 (an infinite light pdf). All of
// a bounce's shadow rays are one batch, traced closest-hit with tmax just short of the light (the tracer interface has
// no any-hit query).
//
// A shadow ray that hits a thin-walled transmissive surface (a window pane) goes on behind it, attenuated by the
// pane's straight-through transmittance (1 - F) x base colour, in another batch: thin-walled refraction does not
// bend light, so this is the same path BSDF sampling finds through the pane, and without it a scene lit through
// glass (Sibenik) would get no sunlight. At most max_depth - 1 - b panes are crossed from the vertex of bounce b,
// so that both strategies cover the same path lengths.
#include <algorithm>

#include "core/error.h"
#include "shading/environment.h"
#include "shading/path_stages.h"

namespace raycoh::path_tracing {

namespace {

struct ShadowRays {
  PixelRays rays;  // make_gbuffer reads this type
  std::vector<uint32_t> pixel;
  std::vector<Vec3> beta;  // the light's contribution if the ray arrives
  std::vector<uint8_t> panes_left;
  std::vector<uint8_t> keep;
};

// The shadow rays of every vertex of this bounce (core/path_vertex.h next_event_rays: slots 2i and 2i + 1),
// compacted in slot order.
ShadowRays make_shadow_rays(const FrameContext& ctx, const Vertices& verts, int bounce) {
  const size_t nv = verts.size();
  ShadowRays shadow;
  shadow.rays.rays.resize(2 * nv);
  shadow.rays.pixel.resize(2 * nv);
  shadow.pixel.resize(2 * nv);
  shadow.beta.resize(2 * nv);
  shadow.panes_left.assign(2 * nv, static_cast<uint8_t>(std::min(255, ctx.settings.max_depth - 1 - bounce)));
  shadow.keep.assign(2 * nv, 0);
  const SunSampler sun(ctx.scene.env);
  const LightsView lights = ctx.emitters.view(ctx.scene);
  RAYCOH_CHECK(!(sun.on && lights.light_count > 0), "the sun and punctual lights would share a shadow-ray slot");
  parallel_for_index(nv, [&](size_t i) {
    ShadowSample out[2];
    const uint32_t p = verts.pixel[i];
    next_event_rays(lights, ctx.scene.env, sun, verts.sp[i], verts.bsdf(i), verts.beta[i], ctx.settings.seed, ctx.frame,
                    p, bounce, out);
    for (size_t k = 0; k < 2; ++k) {
      if (!out[k].found) continue;
      const size_t slot = 2 * i + k;
      shadow.rays.rays[slot] = out[k].ray;
      shadow.beta[slot] = out[k].beta;
      shadow.pixel[slot] = p;
      shadow.keep[slot] = 1;
    }
  });
  compact(shadow.keep, shadow.rays.rays, shadow.pixel, shadow.beta, shadow.panes_left);
  return shadow;
}

// Rounds: unoccluded rays deliver their light; rays stopped by a thin pane go on behind it.
void trace_shadow_rays(FrameContext& ctx, ShadowRays& shadow) {
  while (!shadow.rays.rays.empty()) {
    ctx.trace(shadow.rays.rays, ctx.stats.shadow_rays);
    const std::vector<Hit>& hits = ctx.hits;
    const GBuffer panes = shade_hits(ctx.scene, shadow.rays, hits, ctx.frame);
    const size_t n = shadow.rays.rays.size();
    shadow.keep.assign(n, 0);
    parallel_for_index(n, [&](size_t j) {
      if (!hits[j].valid()) return;
      const ShadingPoint& sp = panes.points[j];
      shadow.keep[j] = pass_pane(sp, panes.materials->bsdf[sp.material], hits[j].t, shadow.rays.rays[j], shadow.beta[j],
                                 shadow.panes_left[j]);
    });
    // Each pixel has at most two shadow rays, in adjacent slots: adding in batch order keeps the order fixed.
    for (size_t j = 0; j < n; ++j)
      if (!hits[j].valid()) ctx.radiance[shadow.pixel[j]] += shadow.beta[j];
    compact(shadow.keep, shadow.rays.rays, shadow.pixel, shadow.beta, shadow.panes_left);
  }
}

}  // namespace

void next_event_estimation(FrameContext& ctx, const Vertices& verts, int bounce) {
  ShadowRays shadow = make_shadow_rays(ctx, verts, bounce);
  trace_shadow_rays(ctx, shadow);
}

}  // namespace raycoh::path_tracing
