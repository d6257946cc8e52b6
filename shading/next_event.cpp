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

// Shadow rays stop this fraction short of the sampled light point, so that the light itself is not an occluder.
constexpr float kShadowEpsilon = 1e-4f;

struct ShadowRays {
  PixelRays rays;  // make_gbuffer reads this type
  std::vector<uint32_t> pixel;
  std::vector<Vec3> beta;  // the light's contribution if the ray arrives
  std::vector<uint8_t> panes_left;
  std::vector<uint8_t> keep;
};

// A light direction from a vertex with what it delivers if unoccluded.
struct LightSample {
  Vec3 dir;
  float tmax;
  Vec3 radiance_over_pdf;
  float pdf;
};

// Fraction of light a thin pane lets through straight, seen along wo from the side of ns (core/bsdf.h's
// thin-walled dielectric: transmitted with probability 1 - F and weight base colour).
Vec3 pane_transmittance(const BsdfParams& m, const ShadingPoint& sp) {
  const float cos_i = std::clamp(dot(sp.wo, sp.ns), 0.f, 1.f);
  return m.base_color * (1.f - fresnel_dielectric(cos_i, m.ior));
}

// Puts the shadow ray of light sample l from vertex i into slot, unless the BSDF gives it nothing.
void add_shadow_ray(ShadowRays& shadow, size_t slot, const Vertices& verts, size_t i, const BsdfParams& m,
                    const LightSample& l) {
  const ShadingPoint& sp = verts.sp[i];
  const DirectionSample e = evaluate_direction(m, sp.ns, sp.ng, sp.wo, l.dir);
  if (!(max_component(e.weight) > 0.f) || !(e.pdf > 0.f)) return;
  const Vec3 f_cos = e.weight * e.pdf;
  shadow.beta[slot] = verts.beta[i] * f_cos * l.radiance_over_pdf * power_heuristic(l.pdf, e.pdf);
  Ray& r = shadow.rays.rays[slot];
  r.org = offset_ray_origin(sp.position, dot(l.dir, sp.ng) >= 0.f ? sp.ng : -sp.ng);
  r.dir = l.dir;
  r.tmin = 0.f;
  r.tmax = l.tmax;
  shadow.pixel[slot] = verts.pixel[i];
  shadow.keep[slot] = 1;
}

// The shadow rays of every vertex of this bounce, compacted in slot order.
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
  const PunctualLights& punctual = ctx.emitters.punctual;
  RAYCOH_CHECK(!(sun.on && !punctual.empty()), "the sun and punctual lights would share a shadow-ray slot");
  parallel_for_index(nv, [&](size_t i) {
    const ShadingPoint& sp = verts.sp[i];
    if (is_delta(sp.cls)) return;
    const uint32_t p = verts.pixel[i];
    const BsdfParams& m = verts.bsdf(i);
    if (!ctx.emitters.empty()) {
      const EmitterSample e = ctx.emitters.sample(ctx.scene, sp, ctx.rand(p, bounce, kEmitterPick),
                                                  ctx.rand(p, bounce, kEmitterU), ctx.rand(p, bounce, kEmitterV));
      if (e.found)
        add_shadow_ray(shadow, 2 * i, verts, i, m,
                       {e.dir, e.dist * (1.f - kShadowEpsilon), e.emission * (1.f / e.pdf), e.pdf});
    }
    if (sun.on) {
      const Vec3 dir = sun.sample(ctx.rand(p, bounce, kSunU), ctx.rand(p, bounce, kSunV));
      add_shadow_ray(shadow, 2 * i + 1, verts, i, m,
                     {dir, __builtin_huge_valf(), ctx.scene.env.sun_radiance * (1.f / sun.pdf), sun.pdf});
    } else if (!punctual.empty()) {
      const PunctualSample l = punctual.sample(ctx.scene, sp, ctx.rand(p, bounce, kLightPick));
      if (l.found)
        add_shadow_ray(shadow, 2 * i + 1, verts, i, m,
                       {l.dir, l.dist * (1.f - kShadowEpsilon), l.irradiance_over_pmf, __builtin_huge_valf()});
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
      const BsdfParams& m = panes.materials->bsdf[sp.material];
      if (!is_thin_pane(m) || shadow.panes_left[j] == 0) return;
      Ray& r = shadow.rays.rays[j];
      r.tmax -= hits[j].t;
      if (!(r.tmax > 0.f)) return;
      r.org = offset_ray_origin(sp.position, -sp.ng);
      shadow.beta[j] = shadow.beta[j] * pane_transmittance(m, sp);
      --shadow.panes_left[j];
      shadow.keep[j] = max_component(shadow.beta[j]) > 0.f;
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
