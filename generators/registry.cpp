// The explicit generator registry: adding a generator is one file (its doc block, parameter table and factory)
// plus one record here.
#include <fmt/format.h>

#include <atomic>
#include <cstdio>

#include "core/error.h"
#include "generators/generator.h"
#include "generators/noopt.h"
#include "generators/tangent_reuse.h"

namespace raycoh {

// Defined in generators/shared_sample.cpp.
const ParamTable& sadeghi_params();
std::unique_ptr<Generator> make_sadeghi_generator(ParamSet& params);
const ParamTable& microjitter_params();
std::unique_ptr<Generator> make_microjitter_generator(ParamSet& params);

const std::vector<GeneratorInfo>& generator_infos() {
  static const std::vector<GeneratorInfo> infos = {
      {"noopt", "baseline: every pixel samples its own BSDF lobe (cosine / GGX VNDF / dielectric)", noopt_params,
       make_noopt_generator},
      {"ours", "the paper: tangent-space direction reuse in interleaved groups of K pixels per tile (Liu et al. 2024)",
       ours_params, make_ours_generator},
      {"contiguous", "ablation: tangent-space reuse in contiguous groups of K pixels, no interleaving, fixed per frame",
       ours_params, make_contiguous_generator},
      {"direct", "ablation: one world-space direction per tile (the paper's Fig. 1; back-facing directions)",
       direct_params, make_direct_generator},
      {"sadeghi",
       "prior art: every pixel uses the frame's shared random numbers, optionally from N x N interleaved streams "
       "(Sadeghi et al. 2009)",
       sadeghi_params, make_sadeghi_generator},
      {"microjitter",
       "prior art: one shared sample per frame, jittered per pixel within a small radius (Dufay et al. 2016)",
       microjitter_params, make_microjitter_generator},
  };
  return infos;
}

std::string generator_name(const std::string& name) { return name == "tile" ? "contiguous" : name; }

const ParamSpec* generator_param_row(const std::string& name, const std::string& param) {
  const std::string registered = generator_name(name);
  for (const GeneratorInfo& info : generator_infos())
    if (info.name == registered)
      for (const ParamSpec& row : info.table())
        if (row.name == param) return &row;
  return nullptr;
}

const ParamSpec* group_size_row(const std::string& name) { return generator_param_row(name, "k"); }

std::unique_ptr<Generator> make_generator(const PluginSpec& spec) {
  const std::string name = generator_name(spec.name);
  if (name != spec.name) {
    static std::atomic<bool> warned{false};  // once per process, however many times a run makes it
    if (!warned.exchange(true))
      std::fprintf(stderr, "warning: generator '%s' is now called '%s'; running '%s'\n", spec.name.c_str(),
                   name.c_str(), name.c_str());
  }
  const GeneratorInfo& info = find_plugin(generator_infos(), "generator", name);
  ParamSet params(fmt::format("generator '{}'", name), spec.params, info.table());
  return info.make(params);
}

}  // namespace raycoh
