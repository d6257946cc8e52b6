#include "pipeline/first_hits.h"

#include <chrono>

#include "tracers/tracer.h"

namespace raycoh {

FirstHits first_hits(const Scene& scene, Tracer& tracer, int width, int height, const std::vector<uint32_t>& order,
                     uint32_t seed, uint32_t frame, bool jitter) {
  FirstHits f;
  f.primary = make_primary_rays(scene.camera, width, height, order, seed, frame, jitter);
  f.hits.resize(f.primary.rays.size());
  const auto t0 = std::chrono::steady_clock::now();
  if (!f.hits.empty()) tracer.trace(f.primary.rays.data(), f.primary.rays.size(), f.hits.data());
  f.trace_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  f.gbuffer = make_gbuffer(scene, f.primary, f.hits);
  return f;
}

}  // namespace raycoh
