// Helpers every generator shares: material parameters, batch writing, statistics.
#include "core/sampling.h"
#include "generators/generator.h"

namespace raycoh {

BsdfParams bsdf_params(const Material& m) {
  BsdfParams b;
  b.cls = m.cls;
  b.base_color = m.base_color;
  b.roughness = m.roughness;
  b.metallic = m.metallic;
  b.ior = m.ior;
  b.thin_walled = m.thin_walled;
  return b;
}

std::vector<uint32_t> hit_pixels_in_order(const GBuffer& gbuffer, const std::vector<uint32_t>& order) {
  std::vector<uint32_t> pixels;
  pixels.reserve(gbuffer.hits);
  for (uint32_t p : order)
    if (gbuffer.points[p].valid()) pixels.push_back(p);
  return pixels;
}

uint32_t emit_ray(RayBatch& out, size_t i, const ShadingPoint& sp, uint32_t pixel, const DirectionSample& s) {
  uint32_t flags = s.flags;
  Ray& ray = out.rays[i];
  if (is_finite(sp.position) && is_finite(sp.ng)) {
    ray.org = offset_ray_origin(sp.position, dot(s.dir, sp.ng) >= 0.f ? sp.ng : -sp.ng);
    out.weight[i] = s.weight;
  } else {
    ray.org = Vec3(0.f);
    out.weight[i] = Vec3(0.f);
    flags |= kSampleNonFinite;
  }
  ray.dir = s.dir;
  ray.tmin = 0.f;
  ray.tmax = __builtin_huge_valf();
  out.pixel[i] = pixel;
  out.pdf[i] = s.pdf;
  out.normal[i] = is_finite(sp.ns) ? sp.ns : s.dir;
  out.material[i] = sp.cls;
  return flags;
}

void tally_ray(uint32_t flags, GenerationStats& stats) {
  ++stats.rays;
  stats.below_geometric += (flags & kSampleBelowGeometric) != 0;
  stats.below_shading += (flags & kSampleBelowShading) != 0;
  stats.non_finite += (flags & kSampleNonFinite) != 0;
}

void merge_stats(GenerationStats& into, const GenerationStats& from) {
  into.rays += from.rays;
  into.below_geometric += from.below_geometric;
  into.below_shading += from.below_shading;
  into.non_finite += from.non_finite;
  for (int i = 0; i < 5; ++i) into.groups[i] += from.groups[i];
  into.hybrid_mean_fallback += from.hybrid_mean_fallback;
  into.reused_rays += from.reused_rays;
}

}  // namespace raycoh
