// The explicit generator registry: adding a generator is one file plus one entry here.
#include <fmt/format.h>

#include "core/error.h"
#include "generators/generator.h"
#include "generators/noopt.h"

namespace raycoh {

const std::vector<GeneratorInfo>& generator_infos() {
  static const std::vector<GeneratorInfo> infos = {
      {"noopt", "baseline: every pixel samples its own BSDF lobe (cosine / GGX VNDF / dielectric)",
       "order=tile|scanline (tile), tile=WxH (8x8, each in [1, 4096])"},
  };
  return infos;
}

std::unique_ptr<Generator> make_generator(const PluginSpec& spec) {
  ParamSet params(fmt::format("generator '{}'", spec.name), spec.params);
  if (spec.name == "noopt") return std::make_unique<NoOptGenerator>(params);
  std::vector<std::string> names;
  for (const auto& info : generator_infos()) names.push_back(info.name);
  throw Error(fmt::format("unknown generator '{}'; valid generators: {}", spec.name, join(names)));
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

std::vector<uint32_t> hit_pixels_in_order(const GBuffer& gbuffer, const std::vector<uint32_t>& order) {
  std::vector<uint32_t> pixels;
  pixels.reserve(gbuffer.hits);
  for (uint32_t p : order)
    if (gbuffer.points[p].valid()) pixels.push_back(p);
  return pixels;
}

}  // namespace raycoh
