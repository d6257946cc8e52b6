// Camera pass of the path tracer (path_stages.h): camera rays through jittered pixel positions in the frame's
// pixel order, traced, and the G-buffer of their hits, which the generator of the first bounce reads (all three
// from pipeline/first_hits.h). A camera ray sees an emitter's radiance on its front face, or the
// environment (sky + sun disc) when it misses; every hit becomes a path vertex with throughput 1 and the camera's
// MIS state (delta).
#include <utility>

#include "pipeline/first_hits.h"
#include "shading/environment.h"
#include "shading/path_stages.h"

namespace raycoh::path_tracing {

GBuffer camera_pass(FrameContext& ctx, const std::vector<uint32_t>& order, Vertices& verts) {
  const RenderSettings& rs = ctx.settings;
  FirstHits first = first_hits(ctx.scene, ctx.tracer, rs.width, rs.height, order, rs.seed, ctx.frame, true);
  ctx.stats.trace_s += first.trace_seconds;
  ctx.stats.primary_rays += first.primary.rays.size();
  const PixelRays& primary = first.primary;
  const GBuffer& gbuffer = first.gbuffer;
  verts.materials = gbuffer.materials;
  for (size_t i = 0; i < primary.rays.size(); ++i) {
    const uint32_t p = primary.pixel[i];
    if (!first.hits[i].valid()) {
      ctx.radiance[p] = environment_radiance(ctx.scene.env, primary.rays[i].dir);
      continue;
    }
    ctx.radiance[p] = FrameContext::emission(*gbuffer.materials, gbuffer.points[p]);
    verts.sp.push_back(gbuffer.points[p]);
    verts.pixel.push_back(p);
    verts.beta.push_back(Vec3(1.f));
    verts.mis.push_back(MisState{});
  }
  return std::move(first.gbuffer);
}

}  // namespace raycoh::path_tracing
