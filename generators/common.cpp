// Helpers every generator shares: material parameters, batch writing, statistics.
#include <fmt/format.h>

#include "core/batch_view.h"
#include "core/error.h"
#include "generators/generator.h"

namespace raycoh {

ParamSpec tile_param(std::pair<int, int> def, const std::string& what) {
  return size_param("tile", def, 1, kMaxTileSide, fmt::format("{}, at most {} pixels", what, kMaxTilePixels));
}

void check_tile(const std::string& owner, std::pair<int, int> tile) {
  const auto [w, h] = tile;
  if (w < 1 || w > kMaxTileSide || h < 1 || h > kMaxTileSide || w * h > kMaxTilePixels)
    throw Error(fmt::format("{}: tile={}x{}: each side must be in [1, {}] and the tile at most {} pixels", owner, w, h,
                            kMaxTileSide, kMaxTilePixels));
}

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

MaterialTable::MaterialTable(const Scene& scene, const GBuffer& gbuffer) {
  if (gbuffer.materials) {
    data_ = gbuffer.materials->bsdf.data();
    size_ = gbuffer.materials->bsdf.size();
    return;
  }
  own_.reserve(scene.materials.size());
  for (const Material& m : scene.materials) own_.push_back(bsdf_params(m));
  data_ = own_.data();
  size_ = own_.size();
}

std::vector<uint32_t> hit_pixels_in_order(const GBuffer& gbuffer, const std::vector<uint32_t>& order) {
  std::vector<uint32_t> pixels;
  pixels.reserve(gbuffer.hits);
  for (uint32_t p : order)
    if (gbuffer.points[p].valid()) pixels.push_back(p);
  return pixels;
}

uint32_t emit_ray(RayBatch& out, size_t i, const ShadingPoint& sp, uint32_t pixel, const DirectionSample& s) {
  return write_ray(batch_view(out), i, sp, pixel, s);
}

void tally_ray(uint32_t flags, GenerationStats& stats) {
  ++stats.rays;
  stats.below_geometric += (flags & kSampleBelowGeometric) != 0;
  stats.below_shading += (flags & kSampleBelowShading) != 0;
  stats.non_finite += (flags & kSampleNonFinite) != 0;
}

size_t hybrid_diffuse_rays(const RayBatch& batch) {
  if (!batch.has_groups()) return 0;
  size_t n = 0;
  for (size_t i = 0; i < batch.size(); ++i) n += is_hybrid_diffuse(batch.group_type[i], batch.material[i]);
  return n;
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
