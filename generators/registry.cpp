// The explicit generator registry: adding a generator is one file plus one entry here.
#include <fmt/format.h>

#include <atomic>
#include <cstdio>

#include "core/error.h"
#include "generators/generator.h"
#include "generators/noopt.h"
#include "generators/tangent_reuse.h"

namespace raycoh {

const std::vector<GeneratorInfo>& generator_infos() {
  static const std::vector<GeneratorInfo> infos = {
      {"noopt", "baseline: every pixel samples its own BSDF lobe (cosine / GGX VNDF / dielectric)",
       "order=tile|scanline (tile), tile=WxH (8x8, each in [1, 4096])"},
      {"ours", "the paper: tangent-space direction reuse in interleaved groups of K pixels per tile (Liu et al. 2024)",
       "tile=WxH (8x8, sides in [1, 1024], WH <= 65536), k=K (8, in [1, WH]), order=tile|group|scanline (tile), "
       "seed=S (0: grouping salt)"},
      {"contiguous", "ablation: tangent-space reuse in contiguous groups of K pixels, no interleaving, fixed per frame",
       "tile=WxH (8x8), k=K (8, in [1, WH]), order=tile|group|scanline (tile), seed=S (0)"},
      {"direct", "ablation: one world-space direction per tile (the paper's Fig. 1; back-facing directions)",
       "tile=WxH (8x8, sides in [1, 1024])"},
  };
  return infos;
}

std::unique_ptr<Generator> make_generator(const PluginSpec& spec) {
  ParamSet params(fmt::format("generator '{}'", spec.name), spec.params);
  if (spec.name == "noopt") return std::make_unique<NoOptGenerator>(params);
  if (spec.name == "ours") return std::make_unique<TangentSpaceReuse>(params, true);
  if (spec.name == "contiguous") return std::make_unique<TangentSpaceReuse>(params, false);
  if (spec.name == "tile") {  // the old name of `contiguous`, kept so that existing command lines still run
    static std::atomic<bool> warned{false};  // once per process, however many times a run makes it
    if (!warned.exchange(true))
      std::fprintf(stderr, "warning: generator 'tile' is now called 'contiguous'; running 'contiguous'\n");
    ParamSet renamed("generator 'contiguous'", spec.params);
    return std::make_unique<TangentSpaceReuse>(renamed, false);
  }
  if (spec.name == "direct") return std::make_unique<DirectReuse>(params);
  std::vector<std::string> names;
  for (const auto& info : generator_infos()) names.push_back(info.name);
  throw Error(fmt::format("unknown generator '{}'; valid generators: {}", spec.name, join(names)));
}

}  // namespace raycoh
