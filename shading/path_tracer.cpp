// Wavefront path tracer on the benchmark's pipeline (docs/design.md sections 1 and 5): the frame loop. One path per
// pixel, frame index = the rng's frame argument; each step is one stage of path_stages.h in its own file:
//   1. Camera pass (camera_pass.cpp): camera rays in 8x8 tile order, traced; the G-buffer of their hits; emitters
//      and the environment seen directly.
//   2. Next-event estimation (next_event.cpp) at every path vertex with a non-delta BSDF: one shadow ray towards
//      an emitter (emitters.cpp) and one towards the sun (core/environment_light.h) or a punctual light (emitters.cpp),
//      MIS-weighted (punctual lights: weight 1), through thin panes.
//   3. Bounce sampling (bounce_sampling.cpp): the generator's directions at the first hit, BSDF sampling and
//      Russian roulette at later ones.
//   4. Hit gathering (hit_gathering.cpp): the wave traced; emitters, sun and sky found by BSDF sampling, MIS-
//      weighted (Veach 1997, ch. 9); the hits become the next vertices.
//   5. Each pixel's frame sample is added to the Accumulator, which counts NaN/Inf samples instead of adding them.
//
// Random numbers: rng(seed, frame, pixel, dim) with, for the vertex of bounce b, dim = kDimFirstFree + 16 b + k:
// k = 0 emitter choice, 1-2 point on it, 3-4 sun cone, 5-6 BSDF direction, 7 lobe choice, 8 roulette, 9 punctual
// light choice. The
// generator uses its own dimensions (core/rng.h) for the first bounce.
#include "shading/path_tracer.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "generators/pixel_order.h"
#include "shading/emitters.h"
#include "shading/path_stages.h"

namespace raycoh {

namespace {

constexpr int kPrimaryTile = 8;

}  // namespace

void RenderSettings::validate() const {
  if (width < 1 || width > 16384 || height < 1 || height > 16384)
    throw Error(fmt::format("resolution {}x{}: width and height must be in [1, 16384]", width, height));
  if (max_depth < 1 || max_depth > 64) throw Error(fmt::format("max depth {}: must be in [1, 64]", max_depth));
  if (rr_depth < 1 || rr_depth > 64) throw Error(fmt::format("roulette depth {}: must be in [1, 64]", rr_depth));
}

void FrameStats::add(const FrameStats& f) {
  wall_s += f.wall_s;
  trace_s += f.trace_s;
  gen_s += f.gen_s;
  primary_rays += f.primary_rays;
  secondary_rays += f.secondary_rays;
  bounce_rays += f.bounce_rays;
  shadow_rays += f.shadow_rays;
  non_finite += f.non_finite;
  merge_stats(generation, f.generation);
  hybrid_diffuse += f.hybrid_diffuse;
}

PathTracer::PathTracer(const Scene& scene, Tracer& tracer, Generator& generator, const RenderSettings& settings)
    : scene_(scene), tracer_(tracer), generator_(generator), settings_(settings) {
  settings_.validate();
  primary_order_ = make_pixel_order(settings_.width, settings_.height, RayOrder::Tile, kPrimaryTile, kPrimaryTile);
  emitters_ = std::make_unique<EmitterDistribution>(scene);
}

PathTracer::~PathTracer() = default;

FrameStats PathTracer::render_frames(uint32_t first, int count, Accumulator& acc) {
  FrameStats total;
  for (int i = 0; i < count; ++i) total.add(render_frame(first + static_cast<uint32_t>(i), acc));
  return total;
}

AuxSample aux_of(const HitMaterials& materials, const ShadingPoint& sp) {
  if (!sp.valid()) return {};
  const BsdfParams& m = materials.bsdf[sp.material];
  const Vec3 albedo = m.cls == MaterialClass::Transmissive ? Vec3(1.f) : vmin(vmax(m.base_color, Vec3(0.f)), Vec3(1.f));
  return {albedo, normalize(sp.ns)};
}

namespace {

void add_aux(const GBuffer& gbuffer, AuxAccumulators& aux) {
  RAYCOH_CHECK(gbuffer.materials != nullptr, "camera pass G-buffer without its material table");
  const HitMaterials& table = *gbuffer.materials;
  path_tracing::parallel_for_index(gbuffer.points.size(), [&](size_t p) {
    const AuxSample s = aux_of(table, gbuffer.points[p]);
    aux.albedo.add(p, s.albedo);
    aux.normal.add(p, s.normal);
  });
}

}  // namespace

void PathTracer::first_hits(uint32_t frame, AuxAccumulators& aux) {
  using namespace path_tracing;
  FrameContext ctx(scene_, *emitters_, tracer_, settings_, frame);
  Vertices verts;
  add_aux(camera_pass(ctx, primary_order_, verts), aux);
}

FrameStats PathTracer::render_frame(uint32_t frame, Accumulator& acc, AuxAccumulators* aux) {
  using namespace path_tracing;
  RAYCOH_CHECK(acc.width() == settings_.width && acc.height() == settings_.height,
               fmt::format("accumulator {}x{} for a {}x{} render", acc.width(), acc.height(), settings_.width,
                           settings_.height));
  const auto t_frame = Clock::now();
  FrameContext ctx(scene_, *emitters_, tracer_, settings_, frame);
  Vertices verts;
  const GBuffer gbuffer = camera_pass(ctx, primary_order_, verts);
  Wave wave;
  for (int bounce = 0; bounce < settings_.max_depth && verts.size() > 0; ++bounce) {
    next_event_estimation(ctx, verts, bounce);
    if (bounce == 0)
      generator_directions(ctx, generator_, gbuffer, wave);
    else
      sample_directions(ctx, verts, bounce, wave);
    gather_hits(ctx, wave, bounce, verts);
  }

  // NaN/Inf samples are counted, not added.
  const uint64_t before = acc.non_finite_samples();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, ctx.radiance.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t p = r.begin(); p < r.end(); ++p) acc.add(p, ctx.radiance[p]);
  });
  ctx.stats.non_finite = acc.non_finite_samples() - before;
  if (aux) add_aux(gbuffer, *aux);
  ctx.stats.wall_s = seconds_since(t_frame);
  return ctx.stats;
}

}  // namespace raycoh
